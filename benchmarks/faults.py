"""Benchmark: fault likelihood on generated cubes, beside a plain semblance and bruges.

Seconds and peak memory of

- ``seismo3d.seismic.faults.fault_likelihood`` (scan over 24 strikes x 6 dips, Hale-style),
- ``thin_faults`` + ``link_faults`` (the rest of fault tracing),
- the whole ``seismo3d faults`` job (``run_faults_job``: read, likelihood, thinning, linking, throw, and every output
  file: volumes, VTK surfaces, CSVs, PNG),
- ``seismo3d.seismic.attributes.semblance`` (structure-oriented, 3 x 3 traces x 9 samples),
- a plain vectorised semblance written here with ``scipy.ndimage.uniform_filter`` (3 x 3 traces x 9 samples, flat
  windows; the cheapest discontinuity attribute one can write with numpy),
- ``bruges.attribute.discontinuity`` (64^3 only: one call computes all three of its methods, Marfurt semblance,
  Gersztenkorn eigen-coherence and gradient structure tensor, in Python loops over windows),

on synthetic 64^3, 128^3 and 256^3 cubes (``seismo3d.data.synthetic.synthetic_cube``, seed 0, noise 0.1).

Each (method, size) runs in its own subprocess so that its peak memory is its own: the cube is loaded from a .npy
file, numba kernels are compiled on a small cube first (compile time is not counted), then the peak resident set
size (``resource.getrusage(...).ru_maxrss``) is read before and after the call; "peak MB" is the increase, i.e. the
memory the method needs on top of its input. "CPU s" is the process CPU time (all threads); with other jobs on the
machine the wall time grows but the CPU time barely moves. "ns/sample" = wall time / number of samples: constant when
time grows linearly with the cube size.

Run: ``python benchmarks/faults.py`` (about 5 minutes on 2 cores, most of it bruges and the 256^3 cube);
``--sizes 64 128`` for a quicker run, ``--no-bruges`` to skip bruges.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

METHODS = ("fault_likelihood", "thin+link", "faults command", "semblance", "plain_semblance", "bruges")
PEERS = {"plain_semblance", "bruges"}


def plain_semblance(cube: np.ndarray, half_samples: int = 4) -> np.ndarray:
    """Marfurt (1998) semblance over 3 x 3 traces and 2 * half_samples + 1 samples, flat windows, vectorised."""
    from scipy.ndimage import uniform_filter, uniform_filter1d

    f = cube.astype(np.float32)
    n = 2 * half_samples + 1
    trace_sum = uniform_filter(f, size=(3, 3, 1), mode="nearest") * 9.0
    energy_sum = uniform_filter(f * f, size=(3, 3, 1), mode="nearest") * 9.0
    num = uniform_filter1d(trace_sum * trace_sum, n, axis=2, mode="nearest")
    den = 9.0 * uniform_filter1d(energy_sum, n, axis=2, mode="nearest")
    return np.where(den > 0, num / np.maximum(den, 1e-30), 1.0).astype(np.float32)


def _rss_mb() -> float:
    """Current resident set size in MB (Linux /proc)."""
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def _worker(method: str, path: str) -> dict:
    from seismo3d import seismic
    from seismo3d.seismic import attributes

    cube = np.load(path)

    def prepare(c):
        """Inputs of the measured call (for thin+link, the likelihood is computed beforehand)."""
        return seismic.fault_likelihood(c) if method == "thin+link" else c

    def call(x):
        if method == "fault_likelihood":
            return seismic.fault_likelihood(x)
        if method == "thin+link":
            thin = seismic.thin_faults(x.likelihood, x.strike_deg, x.dip_deg)
            return seismic.link_faults(thin, x.strike_deg, x.dip_deg)
        if method == "faults command":
            from seismo3d.jobs.faults import run_faults_job

            with tempfile.TemporaryDirectory() as out:
                return run_faults_job(x, out, progress=False)
        if method == "semblance":
            return attributes.semblance(x)
        if method == "plain_semblance":
            return plain_semblance(x)
        if method == "bruges":
            from bruges.attribute import discontinuity

            return discontinuity(x, 9, 1)  # 9-sample windows, dt = 1 sample; computes all 3 methods
        raise ValueError(method)

    if method == "faults command":
        small = Path(tempfile.mkdtemp()) / "warmup.npy"
        np.save(small, np.ascontiguousarray(cube[:32, :32, :48]))
        call(small)  # compile numba kernels outside the measurement
        x = path  # the job reads its input file itself
    else:
        if method != "bruges":
            call(prepare(np.ascontiguousarray(cube[:16, :16, :32])))  # compile numba kernels outside the measurement
        x = prepare(cube)
    rss_before = _rss_mb()
    peak_before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    t_wall, t_cpu = time.perf_counter(), time.process_time()
    call(x)
    wall, cpu = time.perf_counter() - t_wall, time.process_time() - t_cpu
    peak_after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    # the increase of the peak resident set over the memory in use before the call (NaN: no new peak was reached,
    # the call needed less than the earlier peak of loading and warm-up)
    extra = peak_after - rss_before if peak_after > peak_before else float("nan")
    return {"wall": wall, "cpu": cpu, "peak_mb": extra}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[64, 128, 256])
    ap.add_argument("--no-bruges", action="store_true", help="skip bruges.attribute.discontinuity")
    ap.add_argument("--worker", nargs=2, metavar=("METHOD", "NPY"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        print(json.dumps(_worker(*args.worker)))
        return

    from seismo3d.data.synthetic import synthetic_cube

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.sizes:
            cube = synthetic_cube((n, n, n), seed=0).cube
            path = Path(tmp) / f"cube{n}.npy"
            np.save(path, cube)
            del cube
            for method in METHODS:
                if method == "bruges" and (n != 64 or args.no_bruges):
                    continue
                proc = subprocess.run([sys.executable, __file__, "--worker", method, str(path)],
                                      capture_output=True, text=True, check=False)
                if proc.returncode != 0:
                    print(f"{method} {n}^3 failed:\n{proc.stderr[-2000:]}", file=sys.stderr)
                    continue
                res = json.loads(proc.stdout.strip().splitlines()[-1])
                rows.append((method, n, res))
                print(f"  {method:17s} {n:4d}^3  {res['wall']:8.2f} s", file=sys.stderr, flush=True)

    load = os.getloadavg()[0]
    print(f"\nFault likelihood benchmark ({os.cpu_count()} CPUs, load average {load:.1f}, "
          f"numba threads {os.environ.get('NUMBA_NUM_THREADS', 'default')})\n")
    head = f"{'method':22s} {'cube':>6s} {'wall s':>9s} {'CPU s':>9s} {'ns/sample':>10s} {'peak MB':>9s}"
    print(head)
    print("-" * len(head))
    for method, n, res in rows:
        name = method + (" (peer)" if method in PEERS else "")
        print(f"{name:22s} {n:>4d}^3 {res['wall']:9.2f} {res['cpu']:9.2f} {1e9 * res['wall'] / n**3:10.0f} "
              f"{res['peak_mb']:9.0f}")
    print("\nthin+link: thinning and linking only, on the likelihood of the same cube (computed beforehand). peak MB: "
          "increase of the peak resident memory over the memory in use before the call (the input cube, float32: "
          "1, 8 and 64 MB, is not counted).")
    print("bruges.attribute.discontinuity computes its three methods (marfurt, gersztenkorn, gst) in every call.")


if __name__ == "__main__":
    main()
