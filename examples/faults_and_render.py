"""`seismo3d faults --demo` then `seismo3d render`: trace the faults of a generated cube and draw them in 3D.

Run:  python examples/faults_and_render.py [OUTDIR]      (about a minute; no data folder needed)
The same on the command line:
    seismo3d faults --demo -o faults_demo
    seismo3d render faults_demo -o faults_demo/scene.png
"""

# %% Trace the faults of the demo cube (128^3 samples, 3 true faults); outputs go to OUTDIR
import sys
from pathlib import Path

from seismo3d.jobs.faults import run_faults_job
from seismo3d.jobs.render import run_render_job

out = Path(sys.argv[1] if len(sys.argv) > 1 else "faults_demo")
result = run_faults_job(None, out, demo=True, overwrite=True, progress=True)  # overwrite: a rerun replaces the files
for row in result.faults:  # the rows of fault_summary.csv
    print(f"fault {row['id']}: {row['n_points']} samples, strike {row['mean_strike_deg']} deg, dip "
          f"{row['mean_dip_deg']} deg, median throw {row['median_throw_samples']} samples")
print(f"options, inputs and stage times of the run: {result.run_json}")

# %% Render the folder off screen: slices of demo_seismic.sgy, fault surfaces by id, the likelihood volume
job = run_render_job(out, out / "scene.png", overwrite=True)
print(f"{job.n_faults} faults drawn: {job.caption} -> {job.picture}")

# %% The same faults coloured by throw (samples; + where the hanging wall moved down)
job = run_render_job(out, out / "scene_throw.png", color_by="throw", overwrite=True)
print(f"-> {job.picture}")
