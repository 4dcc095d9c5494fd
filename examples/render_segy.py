"""`seismo3d render CUBE.sgy`: a real SEG-Y cube (F3 Netherlands crop) in 3D, placed by its CDP X/Y headers.

Run:  SEISMO3D_DATA_DIR=../shared/data python examples/render_segy.py    (or let the loader fetch the file)
The same on the command line:  seismo3d render f3_crop.sgy -o f3.png --vertical-exaggeration 2
"""

# %% The cube and its geometry from the headers: bin vectors fitted to CDP X/Y, time downward
from seismo3d.data import fetch
from seismo3d.seismic import open_segy
from seismo3d.viz import geometry_of_segy, show_seismic

path = fetch("seismic/f3_crop.sgy")
with open_segy(path) as segy:
    cube = segy.read()
    geometry = geometry_of_segy(segy, vertical_exaggeration=2.0)
print(geometry.describe())
print(f"map unit {geometry.map_unit}; bin vectors (inline, crossline) {geometry.axes[0, :2]}, {geometry.axes[1, :2]}")

# %% Inline, crossline and time-slice planes; screenshot= renders off screen (drop it for a window or Jupyter)
show_seismic(cube, geometry, screenshot="f3_crop.png")
print("-> f3_crop.png")
