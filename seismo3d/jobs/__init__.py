"""What each ``seismo3d`` command does end to end: read its inputs, call the applications, write its outputs.

One module per command, ``seismo3d/jobs/<command>.py``, with one entry point ``run_<command>_job(...)`` that takes the
command's arguments as plain Python values (paths, numbers, strings) and returns what it wrote or measured; the typer
wrapper in :mod:`seismo3d.cli` only parses the command line, calls it and prints. Jobs may import the applications
(:mod:`seismo3d.seismic`, :mod:`seismo3d.terrain`, ...), :mod:`seismo3d.viz` and :mod:`seismo3d.data`; no application
imports a job.

- :mod:`seismo3d.jobs.faults`: ``run_faults_job`` (``seismo3d faults``)
- :mod:`seismo3d.jobs.horizon`: ``run_horizon_job`` (``seismo3d horizon``)
- :mod:`seismo3d.jobs.register`: ``run_register_job`` (``seismo3d register``: point clouds, SEG-Y sub-volumes, and
  terrain files, which it hands to :mod:`seismo3d.jobs.register_terrain`)
- :mod:`seismo3d.jobs.register_terrain`: ``run_register_terrain_job`` (``seismo3d register`` on LAS/LAZ/GeoTIFF)
- :mod:`seismo3d.jobs.match`: ``run_match_job`` (``seismo3d match``)
- :mod:`seismo3d.jobs.lineaments`: ``run_lineaments_job`` (``seismo3d lineaments``)
- :mod:`seismo3d.jobs.plan`: ``run_plan_job`` (``seismo3d plan``)
- :mod:`seismo3d.jobs.map`: ``run_map_job`` (``seismo3d map``: RGB-D sequences)
- :mod:`seismo3d.jobs.convert`: ``run_convert_job`` (``seismo3d convert``)
- :mod:`seismo3d.jobs.render`: ``run_render_job`` (``seismo3d render``)
- :mod:`seismo3d.jobs.evaluate`: ``run_evaluate_job`` (``seismo3d evaluate``: traced faults against people's)

Shared by all: :mod:`seismo3d.jobs.outputs` (the output policy, checked before any input is read),
:mod:`seismo3d.jobs.runinfo` (``run.json`` beside every command's outputs: :class:`~seismo3d.jobs.runinfo.RunRecord`)
and :mod:`seismo3d.jobs.inputs` (seismic inputs opened by :func:`seismo3d.open`, ``read_seismic``, and every
input's kind, ``input_kind``). Each job
returns a result dataclass (paths written, counts, ``stage_seconds``, ``run_json``).
"""
