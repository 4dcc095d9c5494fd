# %% [markdown]
# # 01 Faults in a seismic slab
#
# Fault interpretation of 18 consecutive real inlines of the Penobscot 3D survey (Nova Scotia), with the seven
# horizons people picked on them (Baroni et al. 2020, CC BY 4.0), in one call: `trace_faults` computes the fault
# likelihood (a fault network trained only on generated sections, run on every second inline and crossline at two
# grids, the sections between interpolated), makes it continuous by optimal surface voting (Wu & Fomel 2018), links
# the thinned faults into fault skins, measures each fault's throw by registering the reflectors on its two sides,
# and keeps the faults that show the evidence of one (votes that hold along it, and displaced reflectors or a likely
# fault).
#
# The slab is read from the seismo3d data folder (`SEISMO3D_DATA_DIR`) or, without it, made again from its public
# origin (the 8-bit images and colour masks, downloaded and hash-checked, stacked into the same bytes). The 8-bit
# images are heavily clipped (two thirds of the samples sit at the extremes); the network was trained with such
# clipping and 8-bit quantisation among its degradations.
#
# To run quickly, the notebook traces a window of the slab: the middle 256 traces and samples 450-1089,
# which hold the two deepest of the people's horizons and the top of the faulted interval below them. The whole
# slab (18 x 512 x 1536) takes several times as long.

# %%
%matplotlib inline
import warnings

import numpy as np

from seismo3d.data import load_penobscot_sections
from seismo3d.errors import Seismo3dWarning
from seismo3d.seismic import trace_faults
from seismo3d.viz import cube_geometry, plot_fault_slices, show_seismic

slab = load_penobscot_sections()
print(f"slab (inlines, traces, samples): {slab.cube.shape}, inlines {slab.section_ids[0]}-{slab.section_ids[-1]}")
print(f"live traces: {int(slab.live.sum())} of {slab.live.size}; horizons picked by people: {slab.horizons.shape[1]}")

traces, samples = np.arange(128, 384), np.arange(450, 1090)
cube = slab.cube[:, traces[0]:traces[-1] + 1, samples[0]:samples[-1] + 1]
people = slab.horizons[:, :, traces[0]:traces[-1] + 1] - samples[0]  # picks in samples of the window
people[(people < 0) | (people > samples.size - 1)] = np.nan
inside = [k for k in range(people.shape[1]) if np.isfinite(people[:, k]).mean() > 0.5]
print(f"window (inlines, traces, samples): {cube.shape}; people's horizons inside it: {inside}")

# %% [markdown]
# ## Trace the faults
# One call with the defaults every command uses (`seismo3d faults` runs the same function). seismo3d warns that the
# slab is clipped and that its top is muted; both are expected for this file, so the cell silences those warnings.

# %%
with warnings.catch_warnings():
    warnings.simplefilter("ignore", Seismo3dWarning)
    result = trace_faults(cube, progress=False)

sizes = np.array([f.size for f in result.faults])
spans = np.array([np.ptp(f.points[:, 0]) + 1 for f in result.faults])
throws = {t.fault_id: t for t in result.throws}
print(f"faults traced: {len(result.faults)}")
print(f"faults spanning at least 10 of the 18 inlines: {int((spans >= 10).sum())}")
print(f"fault samples: {sizes.sum()} ({100 * sizes.sum() / cube.size:.2f} % of the window)")
for f, n, span in list(zip(result.faults, sizes, spans))[:5]:
    t = throws.get(f.id)
    throw = f"{t.median_throw:+.1f} samples" if t is not None and np.isfinite(t.median_throw) else "not measured"
    if t is not None and np.isfinite(t.alternative_throw):  # another shift fits the sides about as well
        throw += f", ambiguous: {t.alternative_throw:+.1f} fits the sides {t.ambiguity:.0%} as well"
    print(f"  fault {f.id:>3}: {n:>6} samples over {span:>2} inlines, median throw {throw}")

# %% [markdown]
# A throw is the shift that best aligns the reflectors of the two sides. On reflectors as regular as these, shifts
# a reflector period apart can align them nearly as well: where the best other shift fits at least 40 % as well,
# the throw says so ("ambiguous", with that shift and how well it fits against the throw's: `fault_summary.csv`'s
# `throw_alternative_samples` and `throw_ambiguity`), and its sign, too, may be either. Two of the three throws here
# are ambiguous: check them on the sections before using them.

# %% [markdown]
# ## The slab in 3D
# The first inline, the first trace and the last time slice of the window as a backdrop, in a seismic colour map
# clipped symmetrically at the 99th percentile of the amplitude, the ten largest faults coloured by id, the people's horizons coloured by depth in samples, and the
# fault likelihood as a semi-transparent volume (its top 5 %). Time increases downward; the caption gives the
# vertical exaggeration. In Jupyter with `pip install "seismo3d[notebook]"` (trame) the scene can be turned;
# otherwise it is this picture.

# %%
geometry = cube_geometry(cube.shape, inlines=slab.section_ids, xlines=traces, samples=samples)
largest = result.faults[:10]
backdrop = (0, 0, cube.shape[2] - 1)  # the far sides of the window seen from the default (iso) camera
show_seismic(cube, geometry, slices=backdrop, faults=largest, horizons=[people[:, k] for k in inside],
             likelihood=result.likelihood, window_size=(900, 650));

# %% [markdown]
# The same faults coloured by their throw (samples, positive for normal faults: hanging wall down), without the
# horizons and the likelihood.

# %%
show_seismic(cube, geometry, slices=backdrop, faults=largest, throws=result.throws, color_faults_by="throw",
             cmap="gray", window_size=(900, 650));

# %% [markdown]
# ## Slices
# The most faulted inline, crossline and time slice with every fault drawn over the seismic (above) and the fault
# likelihood (below): the same picture `seismo3d faults` writes as `faults.png`.

# %%
import tempfile
from pathlib import Path

from IPython.display import Image

picture = plot_fault_slices(cube, result.faults, path=Path(tempfile.mkdtemp()) / "faults.png", likelihood=result.likelihood,
                            axes=(slab.section_ids, traces, samples), axis_labels=("inline", "trace", "sample"),
                            title="Penobscot inlines 1075-1092", dpi=70)
Image(filename=picture)
