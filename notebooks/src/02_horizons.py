# %% [markdown]
# # 02 Horizon tracking
#
# seismo3d tracks a horizon from one seed pick by *registering* neighbouring slices: along the seed's inline, each
# panel of traces is registered onto the next with point-to-plane ICP on the reflector points (or fused ICP with
# HOG-pyramid matches), then the horizon is carried inline by inline through the cube. Here it runs on 18 real
# Penobscot inlines against the horizons people picked on them (Baroni et al. 2020), beside a plain amplitude
# autotracker (the same extremum picks, breadth-first from the seed). One seed per horizon: inline 1075, trace 256,
# at the people's pick.
#
# The slab comes from the seismo3d data folder (`SEISMO3D_DATA_DIR`) or is made again from its downloaded origin
# images (hash-checked). `python benchmarks/horizons.py`
# scores all seven horizons, fused ICP and tracking across traced faults.

# %%
%matplotlib inline

import numpy as np

from seismo3d.data import load_penobscot_sections
from seismo3d.seismic import autotrack, horizon_errors, track_horizon
from seismo3d.viz import cube_geometry, plot_horizon_section, show_seismic

slab = load_penobscot_sections()
print(f"slab (inlines, traces, samples): {slab.cube.shape}; live traces scored: {int(slab.live.sum())}")

HORIZONS = (1, 4)  # two of the seven: one crossing the upper, layered interval, one the deeper faulted interval
tracked, plain = {}, {}
for k in HORIZONS:
    people = slab.horizons[:, k]
    seed = (0, 256, people[0, 256])
    tracked[k] = track_horizon(slab.cube, seed, features=None)
    plain[k] = autotrack(slab.cube, seed)

# %% [markdown]
# ## Errors against the people's picks
# In samples, over the live traces: the median absolute error of the tracked traces, the share of traces within 2
# and within 5 samples (an untracked trace counts as a miss) and the coverage.

# %%
print(f"{'horizon':>8} {'tracker':28s} {'median abs':>10} {'within 2':>9} {'within 5':>9} {'coverage':>9}")
for k in HORIZONS:
    for name, horizon in (("seismo3d (point-to-plane)", tracked[k]), ("plain autotracker", plain[k])):
        e = horizon_errors(horizon.times, slab.horizons[:, k])
        print(f"{k:>8} {name:28s} {e.median_abs:>10.2f} {100 * e.within_2:>8.1f}% {100 * e.within_5:>8.1f}% "
              f"{100 * e.coverage:>8.1f}%")

# %% [markdown]
# ## One inline
# Inline 1084 (the middle of the slab), samples 80-359, with the people's picks (wide, pale) and the two trackers'
# horizons (seismo3d dashed, the plain autotracker dotted). Where they agree the lines lie on top of each other.

# %%
i, top, bottom = 9, 80, 360
picks, styles = {}, {}
for n, k in enumerate(HORIZONS):
    for label, times, style in ((f"horizon {k}, people", slab.horizons[i, k], {"lw": 4, "alpha": 0.45}),
                                (f"horizon {k}, seismo3d", tracked[k].times[i], {"ls": "--"}),
                                (f"horizon {k}, plain autotracker", plain[k].times[i], {"ls": ":"})):
        picks[label] = times - top
        styles[label] = {"color": f"C{n}"} | style
plot_horizon_section(slab.cube[i, :, top:bottom], picks, samples=np.arange(top, bottom), styles=styles,
                     title=f"Penobscot inline {slab.section_ids[i]}")

# %% [markdown]
# ## The tracked horizons in 3D
# The upper 400 samples of the slab with the two tracked horizons coloured by their depth in samples, in front of
# the first inline and the first trace (time downward).

# %%
upper = slab.cube[:, :, :400]
geometry = cube_geometry(upper.shape, inlines=slab.section_ids)
show_seismic(upper, geometry, slices=(0, 0, None), horizons=[tracked[k] for k in HORIZONS], window_size=(900, 600));
