"""`make explore`: the design-space sweep on Dask distributed.

    python -m explore.sweep [--size 256] [--rtl-size 32] [--points N] [--scenes a,b] [--jobs 2]
                            [--scheduler tcp://HOST:PORT] [--out out/explore] [--no-docs] [--no-refine]
                            [--plan full|test] [--docs DIR] [--store DIR]
    python -m explore.sweep --keep [--out out/explore] [--store explore/points]

Runs the plan of explore.space (the named configurations, a grid, one-at-a-time steps, then a
refinement around the Pareto front) as one Dask task a point (explore.measure.measure). The
tasks run on a LocalCluster of --jobs worker processes by default, or on the scheduler named by
--scheduler or Dask's own DASK_SCHEDULER_ADDRESS, unchanged. Each point's record is stored
under <out>/points/<hash>.json, the hash of its configuration, the measurement options and the
source it was measured on (explore.measure.source_hash): a sweep that is killed and restarted
redoes only what is missing, and an edit of the RTL or the model measures again. A point not
under <out>/points/ is read from the store (--store, default explore/points/, committed): `--keep`
(make explore-keep) copies the points measured on today's source there and removes those of any
other, so that a sweep longer than one session or one machine's life resumes from a fresh clone. A progress bar
shows points done, failed and left. A failed point (configuration rejected, a scene that does
not fit, a synthesis error, an RTL mismatch) is recorded with its error, never dropped.

Writes <out>/results.json (one record per point, with the configuration itself) and, unless
--no-docs, docs/tradeoffs.md and its plots (explore.report). --points N keeps the first N
points of the plan; --plan test is three cheap points (the tests' sweep). Exit status 2 for a bad argument, before any
work starts.
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from explore import measure, space
from model.cli import Parser, UserError, check_range, progress_bar, run_main
from model.scene.passes import SCENES

ROOT = measure.ROOT
# the committed store: the points of the latest sweep, measured on the source each names (--keep writes it)
STORE = ROOT / "explore" / "points"
RTL_SCENES = ("zone_plate", "seascape")
TRUTH_SS, TRUTH_BAND_SS = measure.TRUTH_SS, measure.TRUTH_BAND_SS


def client_for(scheduler: str | None, jobs: int):
    """A Dask client: the named scheduler (--scheduler, else DASK_SCHEDULER_ADDRESS), else a
    LocalCluster of `jobs` single-threaded worker processes. (client, cluster or None)."""
    from distributed import Client, LocalCluster

    addr = scheduler or os.environ.get("DASK_SCHEDULER_ADDRESS")
    if addr:
        return Client(addr, timeout=30), None
    cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=40)
    return Client(cluster), cluster


def _run_points(client, pts: list[dict], opts: dict, pdir: Path, src: str, progress: bool, phase: str,
                store: Path | None = None) -> list[dict]:
    """The records of `pts`, in order: from <pdir> or the store when stored, else measured on the cluster."""
    from distributed import as_completed

    recs: list = [None] * len(pts)
    todo = {}
    for i, p in enumerate(pts):
        f = pdir / f"{measure.point_key(p['values'], opts, src)}.json"
        kept = store / f.name if store is not None else None
        g = f if f.exists() else kept if kept is not None and kept.exists() else None
        if g is not None:  # stored: under this plan's label (a point `make fit` measured first has its own)
            recs[i] = {**json.loads(g.read_text()), **{k: p[k] for k in ("label", "base", "step")}}
        else:
            todo[i] = f
    stored = len(pts) - len(todo)
    failed = sum(r["status"] != "ok" for r in recs if r)
    bar = progress_bar(progress, len(pts), f"explore {phase}", unit="point", initial=stored, dynamic_ncols=True,
                       leave=True)
    bar.set_postfix(failed=failed, left=len(todo), stored=stored)
    futs = {client.submit(measure.measure, pts[i]["values"], opts, pure=False, key=f"point-{f.stem}"): i
            for i, f in todo.items()}
    for fut in as_completed(futs):
        i = futs[fut]
        try:
            rec = fut.result()
        except Exception as e:  # a worker lost: recorded, never dropped
            rec = {"config": pts[i]["values"], "opts": opts, "status": "failed", "error": f"{type(e).__name__}: {e}"}
        rec.update({"label": pts[i]["label"], "base": pts[i]["base"], "step": pts[i]["step"], "source": src})
        measure.store(todo[i], rec)
        recs[i] = {**rec, "_new": True}
        failed += rec["status"] != "ok"
        bar.update()
        bar.set_postfix(failed=failed, left=len(pts) - bar.n, stored=stored)
    bar.close()
    return recs


def sweep(size: int = 256, rtl_size: int = 32, points: int | None = None, scenes=SCENES, jobs: int = 2,
          scheduler: str | None = None, out: Path | None = None, docs: bool = True, refine: bool = True,
          progress: bool = True, plan: str = "full", docs_dir: Path | None = None,
          corpus_n: int = 40, corpus_size: int = 32, store: Path | None = STORE) -> dict:
    t0 = time.perf_counter()
    out = out or ROOT / "out" / "explore"
    pdir = out / "points"
    pdir.mkdir(parents=True, exist_ok=True)
    opts = {"scenes": list(scenes), "size": size, "rtl_scenes": [s for s in RTL_SCENES if s in scenes] or list(scenes[:2]),
            "rtl_size": rtl_size, "rtl": True, "truth_ss": TRUTH_SS, "truth_band_ss": TRUTH_BAND_SS}
    if corpus_n:  # every point also on the held-out corpus (written once here, read by every worker)
        from explore.validate import HELDOUT_SEED, corpus_dir

        # inside the sweep's output (out/explore/corpus by default), never out/corpus: `make validate` keeps its
        # own N there, and corpus_dir replaces a folder that holds another N (stop 48: a validate run beside a
        # sweep lost its scenes when a sweep worker rewrote out/corpus/seed2 with 40)
        corpus_dir(HELDOUT_SEED, corpus_n, True, out / "corpus")
        opts["corpus"] = {"n": corpus_n, "size": corpus_size}
        opts["corpus_root"] = str(out)
    src = measure.source_hash()
    pts = space.plan(plan)
    pts = pts[:points] if points else pts
    client, cluster = client_for(scheduler, jobs)
    try:
        # the truths first, one task per scene and lattice, so that points never compute one twice
        lattices = {(p["values"]["seed"], p["values"]["hash_bits"]) for p in pts}
        tfuts = [client.submit(_truth_task, s, size, seed, hb, pure=False) for s in scenes for seed, hb in sorted(lattices)]  # noqa: E501
        _wait(tfuts, progress, "explore truths")
        recs = _run_points(client, pts, opts, pdir, src, progress, "plan", store)
        if refine and not points and plan == "full":
            more = space.refine(recs, pts)
            recs += _run_points(client, more, opts, pdir, src, progress, "refine", store)
            pts += more
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    wall = round(time.perf_counter() - t0, 1)
    summary = {"points": len(recs), "ok": sum(r["status"] == "ok" for r in recs),
               "failed": sum(r["status"] != "ok" for r in recs),
               "blocks_synthesized": sum(r.get("blocks_synthesized", 0) for r in recs),
               "blocks_cached": sum(r.get("blocks_cached", 0) for r in recs),
               "wall_seconds": wall, "point_seconds": round(sum(r.get("seconds", 0) for r in recs), 1),
               "measured_now": sum(1 for r in recs if r.get("_new")), "source": src, "opts": opts, "workers": jobs if not scheduler else None,
               "scheduler": scheduler or os.environ.get("DASK_SCHEDULER_ADDRESS") or "LocalCluster"}
    res = {"summary": summary, "records": [{k: v for k, v in r.items() if k != "_new"} for r in recs]}
    tmp = out / "results.json.tmp"
    tmp.write_text(json.dumps(res, indent=1) + "\n")
    tmp.replace(out / "results.json")
    if docs:
        from explore import report

        report.write(res, out, docs_dir)
    return res


def keep(out: Path | None = None, store: Path = STORE) -> dict:
    """`--keep`: the points under <out>/points/ measured on today's source copied into the store
    (written whole, as `measure.store` does), and the store's points of any other source removed."""
    out = out or ROOT / "out" / "explore"
    src = measure.source_hash()
    kept = removed = 0
    store.mkdir(parents=True, exist_ok=True)
    for f in sorted((out / "points").glob("*.json")) if (out / "points").is_dir() else []:
        rec = json.loads(f.read_text())
        if rec.get("source") == src:
            measure.store(store / f.name, rec)
            kept += 1
    for f in sorted(store.glob("*.json")):
        if json.loads(f.read_text()).get("source") != src:
            f.unlink()
            removed += 1
    return {"source": src, "kept": kept, "removed": removed, "in_store": len(list(store.glob("*.json"))),
            "store": str(store)}


def _wait(futs, progress: bool, desc: str) -> None:
    """Wait for `futs` with a progress bar; the first error is raised."""
    from distributed import as_completed

    with progress_bar(progress, len(futs), desc, unit="task", leave=True) as bar:
        for f in as_completed(futs):
            f.result()
            bar.update()


def _truth_task(scene: str, size: int, seed: int, hash_bits: int) -> None:
    from model.hw.config import load_config, variant

    measure.truth(scene, size, variant(load_config("full"), "truth", seed=seed, hash_bits=hash_bits), TRUTH_SS,
                  TRUTH_BAND_SS)


def main(argv=None) -> int:
    ap = Parser(prog="python -m explore.sweep", description="the design-space sweep (make explore)")
    ap.add_argument("--size", type=int, default=256, help="frame side of the image measurements (px)")
    ap.add_argument("--rtl-size", type=int, default=32, help="frame side of the Verilator bit-exact check (px)")
    ap.add_argument("--points", type=int, default=None, help="only the first N points of the plan (no refinement)")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated scenes (default: all)")
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("JOBS", 2)), help="LocalCluster workers")
    ap.add_argument("--scheduler", default=None, help="a Dask scheduler address (default: DASK_SCHEDULER_ADDRESS, "
                                                      "else a LocalCluster)")
    ap.add_argument("--out", type=Path, default=None, help="output root (default out/explore)")
    ap.add_argument("--no-docs", action="store_true", help="results.json only (no docs/tradeoffs.md)")
    ap.add_argument("--no-refine", action="store_true", help="no refinement around the Pareto front")
    ap.add_argument("--plan", choices=("full", "test"), default="full",
                    help="full: explore/space.py's plan; test: three cheap points (the machinery's test)")
    ap.add_argument("--docs", type=Path, default=None, help="where tradeoffs.md and its images go (default docs/)")
    ap.add_argument("--corpus", type=int, default=40, help="held-out corpus scenes every point is measured on (0: none)")
    ap.add_argument("--corpus-size", type=int, default=32)
    ap.add_argument("--store", type=Path, default=STORE,
                    help="where points are read from when not under --out, and --keep writes (default explore/points)")
    ap.add_argument("--keep", action="store_true",
                    help="measure nothing: copy the points of today's source from --out into --store, remove the others")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    a = ap.parse_args(argv)

    def go():
        if a.keep:
            print(json.dumps(keep(a.out, a.store), indent=1))
            return 0
        check_range("--size", a.size, 8, 1024)
        check_range("--rtl-size", a.rtl_size, 2, 512)
        check_range("--jobs", a.jobs, 1, 64)
        check_range("--corpus", a.corpus, 0, 10000)
        check_range("--corpus-size", a.corpus_size, 8, 512)
        if a.points is not None:
            check_range("--points", a.points, 1, 100000)
        scenes = tuple(s.strip() for s in a.scenes.split(",") if s.strip())
        bad = [s for s in scenes if s not in SCENES]
        if bad or not scenes:
            raise UserError(f"--scenes: unknown scene '{bad[0] if bad else a.scenes}' (expected some of {', '.join(SCENES)})")
        res = sweep(a.size, a.rtl_size, a.points, scenes, a.jobs, a.scheduler, a.out, not a.no_docs,
                    not a.no_refine, not a.quiet, a.plan, a.docs, a.corpus, a.corpus_size, a.store)
        print(json.dumps(res["summary"], indent=1))
        return 0 if res["summary"]["points"] else 1

    return run_main("explore", go)


if __name__ == "__main__":
    sys.exit(main())
