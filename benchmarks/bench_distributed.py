"""Issue 15 benchmark: the Orthoglide's dextrous workspace through the executor seam.

* eps = 0.0025 on today's local threads, the same threads with the allocator
  tuned (``tune_malloc``), and a Dask LocalCluster of 1 and 2 worker
  processes: wall time, strong-scaling efficiency T(1) / (2 T(2)), and the
  overhead per chunk (worker time not spent deciding boxes, from Dask's
  task stream, and driver time per chunk);
* eps = 0.00125 with ``max_memory="2GB"`` (boxes streamed to disk, frontier
  depth-first): time, peak resident memory, E / inside;
* a plan on paper for 10 and 100 workers from the measured per-chunk costs.

Each configuration runs in its own process (``run MODE EPS``) so that its
peak resident memory is its own.  Run: python benchmarks/bench_distributed.py
"""

import datetime
import json
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import machine

REFERENCE = "BENCHMARKS.md (issue 4): eps = 0.0025 in 79.2 s on 2 threads, 11 107 454 boxes, peak 1.0 GB"


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def run(mode: str, eps: float) -> dict:
    """One configuration in this process; returns its figures."""
    from workspace_sym import RunOn
    from workspace_sym.interval import executor
    from workspace_sym.orthoglide import Orthoglide

    o = Orthoglide()
    out = {"mode": mode, "eps": eps}
    if mode in ("threads", "threads-tuned"):
        if mode == "threads-tuned":
            executor.tune_malloc()
        d = o.dextrous(eps=eps)
    elif mode == "stream":
        executor.tune_malloc()
        store = Path(tempfile.mkdtemp(prefix="bench-distributed-"))
        try:
            d = o.dextrous(eps=eps, run=RunOn(max_memory="2GB", store=store / "boxes"))
            out["disk_mb"] = sum(f.stat().st_size for f in store.rglob("*.npy")) / 2**20
        finally:
            shutil.rmtree(store)
    else:                                          # dask:N
        from distributed import get_task_stream

        workers = int(mode.split(":")[1])
        waited = [0.0]
        wait = executor.Dask.wait

        def timed_wait(self, futures, timeout):
            t = time.perf_counter()
            try:
                return wait(self, futures, timeout)
            finally:
                waited[0] += time.perf_counter() - t

        executor.Dask.wait = timed_wait
        t = time.perf_counter()
        with executor.connect(f"local:{workers}") as client:
            client.run(lambda: __import__("workspace_sym.orthoglide"))      # warm workers: imports not timed
            out["cluster_start_s"] = time.perf_counter() - t
            with get_task_stream(client) as stream:
                d = o.dextrous(eps=eps, run=RunOn(executor=client))
            tasks = [s["stop"] - s["start"] for event in stream.data if "call_in_worker" in str(event["key"])
                     for s in event["startstops"] if s["action"] == "compute"]
            out["chunks"] = len(tasks)
            out["compute_s"] = sum(tasks)
            out["worker_peak_mb"] = sum(client.run(peak_mb).values())
        out["driver_busy_s"] = d.paving.seconds - waited[0]
    data = d.to_dict()
    out.update(seconds=data["seconds"], evaluated=data["boxes_evaluated"], inside=data["volume_inner"],
               E=data["volume_undecided"], boxes=data["boxes"], peak_mb=peak_mb())
    return out


def child(mode: str, eps: float) -> dict:
    proc = subprocess.run([sys.executable, __file__, "run", mode, str(eps)], capture_output=True, text=True,
                          check=True, cwd=Path(__file__).parent)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main():
    print(f"# bench_distributed  {datetime.date.today()}  {machine()}")
    print(f"reference: {REFERENCE}")
    rows = {}
    for mode in ("threads", "threads-tuned", "dask:1", "dask:2"):
        r = rows[mode] = child(mode, 0.0025)
        extra = ""
        if "chunks" in r:
            extra = (f", {r['chunks']} chunks, compute {r['compute_s']:.1f} s, driver busy {r['driver_busy_s']:.1f} s, "
                     f"workers' peak {r['worker_peak_mb']:.0f} MB, cluster start {r['cluster_start_s']:.1f} s")
        print(f"eps = 0.0025, {mode}: {r['seconds']:.1f} s, {r['evaluated']} boxes, inside {r['inside']:.4f}, "
              f"E {r['E']:.4f}, peak {r['peak_mb']:.0f} MB{extra}")
    same = {json.dumps([r["evaluated"], r["inside"], r["E"], r["boxes"]]) for r in rows.values()}
    print(f"same answer in every mode: {len(same) == 1}")
    t1, t2 = rows["dask:1"], rows["dask:2"]
    print(f"strong scaling, 1 -> 2 workers: speed-up {t1['seconds'] / t2['seconds']:.2f}, efficiency "
          f"{t1['seconds'] / (2 * t2['seconds']):.0%}")
    for r in (t1, t2):
        workers = int(r["mode"].split(":")[1])
        overhead = (workers * r["seconds"] - r["compute_s"]) / r["chunks"]
        r["overhead_per_chunk"] = overhead
        print(f"{r['mode']}: mean compute per chunk {r['compute_s'] / r['chunks'] * 1e3:.0f} ms, overhead per chunk "
              f"(worker time not computing) {overhead * 1e3:.0f} ms, driver time per chunk "
              f"{r['driver_busy_s'] / r['chunks'] * 1e3:.1f} ms")
    # Plan on paper: T(W) = max(N (c + o) / W, N d), with N chunks, c compute, o overhead, d driver time per chunk.
    N, c = t2["chunks"], t2["compute_s"] / t2["chunks"]
    o, d = t2["overhead_per_chunk"], t2["driver_busy_s"] / t2["chunks"]
    for w in (10, 100):
        T = max(N * (c + o) / w, N * d)
        print(f"plan, {w} workers at eps = 0.0025: {T:.1f} s (compute-bound {N * (c + o) / w:.1f} s, driver-bound "
              f"{N * d:.1f} s); at eps = 0.00125 (about 4x the chunks): {4 * T:.1f} s")
    r = child("stream", 0.00125)
    print(f"eps = 0.00125, threads (allocator tuned) + max_memory 2GB: {r['seconds']:.1f} s, {r['evaluated']} boxes, "
          f"inside {r['inside']:.4f}, E {r['E']:.4f}, E / inside {100 * r['E'] / r['inside']:.2f} %, peak "
          f"{r['peak_mb']:.0f} MB, {r['disk_mb']:.0f} MB on disk, boxes {r['boxes']}")
    print("machine shared with other jobs during the runs: times are indicative")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "run":
        print(json.dumps(run(sys.argv[2], float(sys.argv[3]))))
    else:
        main()
