"""The public names of seismo3d.seismic and its sub-packages: every name in an ``__all__`` is importable from there,
and the package's ``__all__`` lists each name once."""

import importlib

import pytest

import seismo3d.seismic

SUBPACKAGES = ["seismo3d.seismic.io", "seismo3d.seismic.faults", "seismo3d.seismic.horizons",
               "seismo3d.seismic.volumes"]


@pytest.mark.parametrize("package", ["seismo3d.seismic", *SUBPACKAGES])
def test_every_name_in_all_is_importable(package):
    module = importlib.import_module(package)
    missing = [name for name in module.__all__ if not hasattr(module, name)]
    assert not missing, f"{package}.__all__ names what it does not define: {missing}"
    namespace = {}
    exec(f"from {package} import *", namespace)  # noqa: S102 - the star import uses __all__
    assert set(module.__all__) <= set(namespace)


@pytest.mark.parametrize("package", ["seismo3d.seismic", *SUBPACKAGES])
def test_all_has_no_duplicates(package):
    names = importlib.import_module(package).__all__
    assert len(names) == len(set(names)), sorted({n for n in names if names.count(n) > 1})


def test_the_package_exports_what_it_did_before_the_sub_packages():
    # link_faults, the region-growing linker that fault skins replaced, was removed (dead code; issue 53); LazyCube
    # and open_lazy too: seismo3d.open's DataArray is the one cube type, lazy for files (issue 75)
    before = {
        "POLARITIES", "Fault", "FaultCrossings", "FaultInterpretation", "FaultLikelihood", "FaultScanOptions",
        "FaultTracingOptions", "FaultVotes", "SkinOptions", "VotingOptions", "fault_skins",
        "vote_faults", "FaultScores", "FaultThrow", "Horizon", "HorizonErrors", "ReflectorOrientation",
        "RegistrationErrors", "SeismicCube", "ThrowOptions", "TrackingOptions", "VolumeOptions",
        "VolumeRegistration", "autotrack", "discontinuity", "eigen_coherence", "evaluate_faults", "fault_labels",
        "fault_likelihood", "fault_normals", "fault_throw", "fault_throws", "fill_horizon", "horizon_errors",
        "open_segy", "read_ascii_lines", "read_section", "read_segy", "reflector_picks",
        "reflector_points", "register_volumes", "registration_errors", "reliable_throw", "resample_volume",
        "semblance", "structure_tensor_orientation", "thin_faults", "trace_faults", "track_horizon",
        "volume_spacing", "write_horizon_text", "write_like",
    }
    assert before <= set(seismo3d.seismic.__all__)


@pytest.mark.parametrize("package", SUBPACKAGES[:3])
def test_sub_package_names_are_the_objects_of_their_modules(package):
    """A sub-package's names are re-exports: the same objects as in the modules that define them."""
    module = importlib.import_module(package)
    for name in module.__all__:
        obj = getattr(module, name)
        home = getattr(obj, "__module__", None)
        if home and home.startswith(package + "."):
            assert getattr(importlib.import_module(home), name) is obj
