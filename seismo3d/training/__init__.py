"""Training of seismo3d's learned models (needs the optional ``train`` extra: ``pip install seismo3d[train]``).

* :mod:`seismo3d.training.fault_unet`: the fault network of
  :func:`seismo3d.seismic.faults.likelihood.learned.learned_fault_likelihood`, trained on generated sections
  (:mod:`seismo3d.data.synthetic_sections`); ``python -m seismo3d.training.fault_unet --help``.
* :mod:`seismo3d.training.export_onnx`: the ONNX model of trained weights (:func:`~.export_onnx.onnx_model`), the file
  the package ships; ``python -m seismo3d.training.export_onnx --help``.
* :mod:`seismo3d.training.adapt`: the network fine-tuned on an interpreter's picks (``seismo3d adapt``), with its
  options in :mod:`seismo3d.training.adapt_options`, the one module here that imports without PyTorch.

No application imports this package (the ``adapt`` command's job does): inference runs in ONNX Runtime
(:mod:`seismo3d.seismic.faults.likelihood.network`).
"""
