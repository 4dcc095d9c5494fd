"""`seismo3d horizon`: track a horizon in a SEG-Y cube from one seed pick, then render it.

Run:  python examples/track_horizon.py       (writes a generated cube first; no data folder needed)
The same on the command line:
    seismo3d horizon cube.sgy --seed 108,516,240 -o horizon.txt
    seismo3d render horizon.txt --seismic cube.sgy -o horizon.png
"""

# %% A generated 16 x 24 x 96 cube with known horizons, written as SEG-Y (inlines 100.., crosslines 500.., 4 ms)
import numpy as np
import segyio

from seismo3d.data import synthetic_cube
from seismo3d.jobs.horizon import run_horizon_job
from seismo3d.jobs.render import run_render_job
from seismo3d.seismic import horizon_errors

syn = synthetic_cube((16, 24, 96), n_faults=0, seed=4, noise=0.05)
segyio.tools.from_array3D("cube.sgy", syn.cube, iline=189, xline=193, format=5, dt=4000)
with segyio.open("cube.sgy", ignore_geometry=True) as f:
    print(f"cube.sgy: {f.tracecount} traces of {len(f.samples)} samples")

# %% Track the generator's horizon 1 from a seed on the middle trace (inline number, crossline number, time in ms)
truth = syn.horizons[1]
polarity = "peak" if syn.horizon_polarity[1] > 0 else "trough"
seed = (1 + 8, 1 + 12, 4.0 * truth[8, 12])  # from_array3D numbers lines from 1
job = run_horizon_job("cube.sgy", [seed], "horizon.txt", polarity=polarity, overwrite=True, progress=False)
errors = horizon_errors(job.horizon.times, truth)
print(f"{job.n_rows} traces tracked; median error {errors.median_abs:.2f} samples, {100 * errors.within_2:.0f} % "
      "within 2 samples of the truth")

# %% Draw it over the cube
print(run_render_job("horizon.txt", "horizon.png", seismic="cube.sgy", overwrite=True).caption, "-> horizon.png")
