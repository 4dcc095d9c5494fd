"""The resumable Zarr stores of a run by blocks: a work folder of intermediate arrays and markers, the output
assembled in ``OUTPUT.partial`` and renamed to ``OUTPUT`` only when every block is done (an output that exists is
complete), and its coordinates; what an earlier run left there, and whether it is reused, resumed or refused
(:func:`earlier_run`, the one place that decides it).

:class:`StoreRun` adds the stores to :class:`~seismo3d.seismic.blocks.executor.BlockRun` (markers, tasks, schedulers);
what the blocks compute is the declared steps' (:mod:`~seismo3d.seismic.blocks.apply`; the fault runs by blocks:
:mod:`seismo3d.seismic.faults.likelihood.scan_blocks`, :mod:`seismo3d.seismic.faults.likelihood.learned_blocks`,
:mod:`seismo3d.seismic.faults.surfaces.blocks`).
"""

from __future__ import annotations

import json
import os
import pathlib
import shutil
from dataclasses import asdict, dataclass, field, is_dataclass

import numpy as np

from ...errors import EarlierStoresError, InputError
from ..io.zarr_store import SEISMIC_CODEC, consolidate
from .executor import BlockRun
from .options import ChunkOptions

__all__ = ["EarlierRun", "StoreRun", "earlier_run", "read_sheared", "write_coords"]


@dataclass(frozen=True)
class EarlierRun:
    """What an earlier run by blocks left where a run writes its Zarr store (:func:`earlier_run`).

    Attributes
    ----------
    state : {'none', 'finished', 'unfinished', 'another'}
        Nothing there; the finished store of the same run (reused); the work folder of the same run, unfinished
        (resumed, with its block plan); the store or work folder of another run (refused, or set aside by a caller
        that may replace it).
    paths : tuple of pathlib.Path
        The entries found: the store, its ``.partial`` output and its ``.work`` folder, those that exist.
    attrs : dict
        The finished store's attributes (state ``'finished'`` or ``'another'``), else empty.
    record : dict
        What the earlier run recorded of itself: the finished store's ``run`` attribute with its ``source``, or the
        unfinished run's manifest (with its block plan, ``'plan'``); empty when unreadable.
    """

    state: str
    paths: tuple = ()
    attrs: dict = field(default_factory=dict)
    record: dict = field(default_factory=dict)


def earlier_run(out, record: dict) -> EarlierRun:
    """What an earlier run left at the Zarr store ``out`` (and its ``OUTPUT.work`` folder), and whether it is this
    run's: the one decision of every run by blocks between reusing a finished store, resuming an unfinished one, and
    refusing (or, when the caller may, setting aside) the stores of another run.

    A run is the same when every item of ``record`` but its block plan (``'plan'``: a resumed run keeps its own
    blocks) equals what the earlier run recorded: the finished store its ``run`` attribute (with the ``source``
    attribute its caller added), an unfinished one the work folder's ``manifest.json``; an item the earlier run did
    not record is not compared (a caller that knows only the input, shape and options asks with those). A finished
    store that records no run, or is not complete, is another run's.

    Parameters
    ----------
    out : str or os.PathLike
        The store a run by blocks writes.
    record : dict
        What the run computes from, JSON-serialisable (the shape, the options, the input's ``source``...): its
        manifest (:meth:`StoreRun.start_output`), or the part of it a caller knows.

    Returns
    -------
    EarlierRun
    """
    import zarr

    out = pathlib.Path(out)
    work, partial = out.with_name(out.name + ".work"), out.with_name(out.name + ".partial")
    paths = tuple(p for p in (out, partial, work) if os.path.lexists(p))
    wanted = json.loads(json.dumps(record, default=str))

    def same(found) -> bool:
        return isinstance(found, dict) and all(found[k] == v for k, v in wanted.items() if k != "plan" and k in found)

    if os.path.lexists(out):
        try:
            attrs = dict(zarr.open_group(str(out), mode="r").attrs)
        except Exception:  # noqa: BLE001 - anything that is not our Zarr group: another run's (or none's)
            attrs = {}
        run = attrs.get("run")
        found = dict(run, **({"source": attrs["source"]} if "source" in attrs else {})) if run else None
        state = "finished" if attrs.get("complete") is True and same(found) else "another"
        return EarlierRun(state, paths, attrs, found or {})
    if os.path.lexists(work):
        try:
            manifest = json.loads((work / "manifest.json").read_text())
        except (OSError, ValueError):
            manifest = None
        return EarlierRun("unfinished" if same(manifest) else "another", paths, {}, manifest or {})
    return EarlierRun("none", paths)


class StoreRun(BlockRun):
    """The folders of a run by blocks into one output Zarr group: the work folder (``OUTPUT.work``) with its
    intermediate arrays and markers, the output assembled in ``OUTPUT.partial`` and renamed to ``OUTPUT`` when
    complete.

    Parameters
    ----------
    out : pathlib.Path
        The output Zarr group.
    chunking : ChunkOptions
        The scheduler and the blocks computed at once.
    progress : bool
        Report progress per finished block.
    outputs : tuple of str
        Names of the output arrays, each ``(n_inlines, n_xlines, n_samples)`` float32 with dimensions inline,
        crossline, sample.
    """

    def __init__(self, out: pathlib.Path, chunking: ChunkOptions, progress: bool,
                 outputs: tuple = ("likelihood", "strike_deg", "dip_deg")):
        super().__init__(out.with_name(out.name + ".work"), scheduler=chunking.scheduler, workers=chunking.workers,
                         progress=progress)
        self.out, self.chunking, self.outputs = out, chunking, tuple(outputs)
        self.partial = out.with_name(out.name + ".partial")
        self.manifest = None  # what it computes (start_output), recorded in the finished output

    def start_output(self, manifest: dict, shape, tile: int, work_arrays) -> None:
        """Refuse an existing output or a missing folder, open the work folder with ``manifest``, and create the
        work arrays ``(name, dtype, samples per trace)`` and the output arrays that do not exist yet.

        Parameters
        ----------
        manifest : dict
            What is computed (:meth:`~seismo3d.seismic.blocks.executor.BlockRun.open`).
        shape : (int, int, int)
            ``(n_inlines, n_xlines, n_samples)``.
        tile : int
            Traces a side of the arrays' chunks (:attr:`~seismo3d.seismic.blocks.options.ChunkOptions.tile`).
        work_arrays : iterable of (str, str, int) or (str, str, int, bool)
            Name, dtype and samples per trace of each intermediate array in the work folder, and whether it is
            compressed (default: not). Every array is named in :attr:`~seismo3d.seismic.blocks.executor.BlockRun.arrays`
            for the declared steps.

        Raises
        ------
        InputError
            The output exists, or its folder does not.
        EarlierStoresError
            The work folder holds an unfinished run of something else (:func:`earlier_run`).
        """
        import zarr
        if self.out.exists():
            raise InputError(f"output {self.out} already exists; pick another output or delete it")
        if not self.out.parent.is_dir():
            raise InputError(f"cannot write {self.out}: folder {self.out.parent} does not exist; create it first")
        if earlier_run(self.out, manifest).state == "another":
            raise EarlierStoresError(f"{self.work} holds an unfinished run of another cube or other options; delete "
                                     f"{self.work} and {self.partial} to start afresh, or rerun with the same input "
                                     "and options to resume it", [self.work])
        self.open(manifest)
        self.manifest = manifest
        n0, n1, nt = shape
        t = tile
        self.shape = tuple(shape)
        self.arrays.update({name: str(self.partial / name) for name in self.outputs})
        for name, dtype, n, *compressed in work_arrays:
            self.arrays[name] = str(self.work / name)
            if not (self.work / name).exists():
                zarr.create_array(str(self.work / name), shape=(n0, n1, n), chunks=(t, t, n), dtype=dtype,
                                  fill_value=0, **({} if compressed and compressed[0] else {"compressors": None}))
        if not self.partial.exists():
            group = zarr.open_group(str(self.partial), mode="w")
            for name in self.outputs:
                group.create_array(name, shape=(n0, n1, nt), chunks=(t, t, nt), dtype="float32", fill_value=0,
                                   compressors=SEISMIC_CODEC, dimension_names=("inline", "crossline", "sample"))

    def manifest_for(self, shape, options, plan, **more) -> dict:
        """The run's manifest: what it computes from, and its block plan, the plan of an unfinished run of the same
        work (:func:`earlier_run`) in place of ``plan``: a resumed run keeps its blocks even when the memory left for
        it has changed.

        Parameters
        ----------
        shape : (int, int, int)
            ``(n_inlines, n_xlines, n_samples)``.
        options : dataclass
            The computation's options.
        plan : dict or dataclass
            The blocks planned under the memory limit.
        **more
            Other entries a resumed or reused run must match (e.g. the input it reads).

        Returns
        -------
        dict
            ``shape``, ``options``, ``plan`` and ``more``, as JSON reads them back (the plan to run: ``['plan']``);
            for :meth:`start_output`.
        """
        plan = asdict(plan) if is_dataclass(plan) else plan
        manifest = json.loads(json.dumps({"shape": list(shape), "options": asdict(options), "plan": plan, **more},
                                         default=str))
        earlier = earlier_run(self.out, manifest)
        if earlier.state == "unfinished":
            manifest["plan"] = earlier.record["plan"]
        return manifest

    def finished_output(self, manifest: dict, what: str) -> dict | None:
        """The attributes of the finished output of this same run (:func:`earlier_run`: its ``run`` attribute equal
        to ``manifest``, the block plan aside: blocks do not change the result), or None when there is no output
        yet.

        Raises
        ------
        EarlierStoresError
            The output exists but is not the finished output of this run (``what`` says what must be the same).
        """
        if not self.out.exists():
            return None
        earlier = earlier_run(self.out, manifest)
        if earlier.state != "finished":
            raise EarlierStoresError(f"output {self.out} already exists and is not the finished output of this "
                                     f"{what}; pick another output or delete it", [self.out])
        return earlier.attrs

    def write_gathered(self, step: str, blocks, columns: dict, n: int, *, points: str = "points") -> None:
        """Gather a step's sparse lists into 1-D arrays of the output group, in the C order of their ``points``
        (``(k, 3)`` sample indices of the cube), a row of blocks at a time.

        Parameters
        ----------
        step : str
            The step's name (its lists: :meth:`~seismo3d.seismic.blocks.executor.BlockRun.lists_reader`).
        blocks : list of tuple
            The step's blocks.
        columns : dict
            ``{list name: (output array name, dtype)}``; the ``points`` list is written ``(n, 3)``, the others
            ``(n,)``.
        n : int
            Items over all blocks.
        points : str
            The list of sample indices that orders the items.
        """
        import zarr

        group = zarr.open_group(str(self.partial), mode="r+")
        out = {k: group.create_array(name, shape=(n, 3) if k == points else (n,), dtype=dtype, overwrite=True,
                                     chunks=(1 << 20, 3) if k == points else (1 << 20,))
               for k, (name, dtype) in columns.items()}
        start = 0
        for i0 in sorted({b[0] for b in blocks}):  # a row of blocks at a time: its items in C order (the cube's)
            row = self.gathered_lists(step, [b for b in blocks if b[0] == i0], columns)
            order = np.argsort(np.ravel_multi_index(tuple(row[points].T), self.shape), kind="stable")
            m = int(order.size)
            if m:
                for key, array in out.items():
                    array[start:start + m] = row[key][order].astype(array.dtype)
            start += m

    def describe(self, coords, attrs: dict) -> None:
        """Write the 1-D coordinates (:func:`write_coords`) and ``attrs`` into the output being assembled
        (``OUTPUT.partial``), before :meth:`finish`.

        Parameters
        ----------
        coords : dict or None
            As :func:`write_coords`'s.
        attrs : dict
            JSON-serialisable attributes of the output group (e.g. the method, a statistic of the run).
        """
        import zarr
        group = zarr.open_group(str(self.partial), mode="r+")
        write_coords(group, self.shape, coords)
        group.attrs.update(attrs)

    def finish(self, attrs: dict | None = None) -> None:
        """Mark the output complete (with ``attrs``, its other attributes, and ``run``: the manifest it was computed
        from, which a later run compares with its own, :func:`earlier_run`), rename it into place and delete the work
        folder."""
        import zarr
        attrs = {"run": self.manifest, **dict(attrs or {}), "complete": True}
        zarr.open_group(str(self.partial), mode="r+").attrs.update(attrs)
        consolidate(self.partial)
        os.replace(self.partial, self.out)
        shutil.rmtree(self.work, ignore_errors=True)


def write_coords(group, shape, coords) -> None:
    """Write the 1-D coordinates ``inline``, ``crossline`` and ``sample`` beside a group's arrays.

    Parameters
    ----------
    group : zarr.Group
        Opened for writing.
    shape : (int, int, int)
        ``(n_inlines, n_xlines, n_samples)``.
    coords : dict or None
        ``inline``, ``crossline`` (numbers) and ``sample`` (times or depths), with an optional ``sample_unit``
        string; a coordinate left out is written as indices.

    Raises
    ------
    InputError
        A coordinate whose length is not its axis's.
    """
    coords = dict(coords or {})
    unit = coords.pop("sample_unit", None)
    for name, n in zip(("inline", "crossline", "sample"), shape):
        values = np.asarray(coords.get(name, np.arange(n)))
        if values.shape != (n,):
            raise InputError(f"coordinate {name!r} must have {n} values; got shape {values.shape}")
        arr = group.create_array(name, shape=(n,), dtype=values.dtype, dimension_names=(name,), overwrite=True)
        arr[:] = values
        if name == "sample" and unit:
            arr.attrs["units"] = unit


def read_sheared(array, region, axis: int, tile: int) -> np.ndarray:
    """A region of a stored ``(n0, n1, m)`` array in a layout with ``axis`` first and the other lateral axis last,
    read tile row by tile row so that only one row is held twice.

    Parameters
    ----------
    array : zarr.Array
        ``(n0, n1, m)``.
    region : (slice, slice)
        Inlines and crosslines read (``start:stop``).
    axis : {0, 1}
        The lateral axis put first.
    tile : int
        Rows read at once along ``axis``.

    Returns
    -------
    (n_axis, m, n_other) float32 ndarray
    """
    rows, cols = region
    n_a = (rows.stop - rows.start) if axis == 0 else (cols.stop - cols.start)
    n_b = (cols.stop - cols.start) if axis == 0 else (rows.stop - rows.start)
    out = np.empty((n_a, array.shape[2], n_b), dtype=np.float32)
    start = rows.start if axis == 0 else cols.start
    for a in range(0, n_a, tile):
        b = min(a + tile, n_a)
        if axis == 0:
            out[a:b] = array[start + a:start + b, cols].transpose(0, 2, 1)
        else:
            out[a:b] = array[rows, start + a:start + b].transpose(1, 2, 0)
    return out
