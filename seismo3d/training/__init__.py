"""Training of seismo3d's learned models (needs the optional ``train`` extra: ``pip install seismo3d[train]``).

* :mod:`seismo3d.training.fault_unet`: the fault network of
  :func:`seismo3d.seismic.faults.likelihood.learned.learned_fault_likelihood`, trained on generated sections
  (:mod:`seismo3d.data.synthetic_sections`); ``python -m seismo3d.training.fault_unet --help``.

Nothing in seismo3d imports this package: inference runs in numpy (:mod:`seismo3d.seismic.faults.likelihood.network`).
"""
