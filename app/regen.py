"""`make regen`: every command behind a stamped doc run again, on two lanes at once.

Each generated doc (or each section of a doc several commands share, docs/verification.md) ends with
a stamp, `<!-- measured on: <config>=<hash> ... rtl=<hash> -->`; tests/test_validate.py fails when a
stamp names another rtl/ or configuration than today's. After a change to rtl/ every stamp is stale:
this command reruns what each stale section was written by (JOBS below: the section, its commands,
their minutes from an empty cache on the 2-core machine, what must run first), the longest first, on
--jobs lanes (default 2, one job a lane: the jobs themselves use one core each, or say so), each job's
output in out/regen/<job>.log; then every section still stale is marked so, a line under its heading
naming what it was measured on and the command (--mark does only that): nothing stale looks current,
and tests/test_validate.py holds it (a stale section without its mark fails, as does a mark on a
current one). --all reruns every section; --dry-run prints the plan; --only JOB[,JOB] picks jobs.

    python -m app.regen [--all] [--dry-run] [--mark] [--only synth,frames] [--jobs 2]      (make regen)

The commands are the docs' own: `make filters`' flags are read from docs/filters.md's first line, the
animations from docs/images/animation.json (one per section of docs/animation.md).
"""
from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
import threading
import time
from dataclasses import dataclass

from app.gls import GLS_CONFIGS
from model.cli import Parser, UserError, check_range, progress_bar, run_main
from model.hw.config import ROOT, STAMP, config_hash, read_stamp, rtl_source_hash, stamped_config

DOCS = ROOT / "docs"
LOGS = ROOT / "out" / "regen"
BANNER = "> **Stale:**"  # the first words of the line that marks a stale section (mark())


@dataclass(frozen=True)
class Job:
    name: str
    section: tuple[str, str | None]  # (doc path under docs/, "## " section title or None: the whole doc)
    commands: tuple[str, ...]        # commands, run in ROOT one after another ("-" first: its exit status is a result)
    minutes: float                   # from an empty cache, on this project's 2-core machine (docs/verification.md)
    after: tuple[str, ...] = ()      # jobs that must end first (they fill a cache this one reads)


def _filters_command() -> str:
    if not (DOCS / "filters.md").is_file():
        return "make filters"
    head = [x for x in (DOCS / "filters.md").read_text().splitlines()[:8] if not x.startswith(BANNER)]
    m = re.search(r'`(make filters FILTERS_FLAGS="[^"]*")`', "\n".join(head))
    if not m:
        raise UserError("docs/filters.md: its first paragraph names no `make filters FILTERS_FLAGS=\"...\"` command")
    return m.group(1)


def _animation_commands() -> tuple[str, ...]:
    state = DOCS / "images" / "animation.json"
    cmds = tuple(json.loads(state.read_text())) if state.is_file() else ()
    bad = [c for c in cmds if not c.startswith("make animation ")]
    if bad:
        raise UserError(f"{state}: a section's command is not `make animation ...`: {bad[0]!r}")
    return cmds or ("make animation",)


def _validate_commands() -> tuple[str, ...]:
    """Each section's own `make validate CONFIG=... N=... SIZE=...` line of docs/validation.md."""
    if not (DOCS / "validation.md").is_file():
        return ("make validate",)
    cmds = tuple(re.findall(r"^`(make validate CONFIG=\S+ N=\d+ SIZE=\d+)`", (DOCS / "validation.md").read_text(), re.M))
    if not cmds:
        raise UserError("docs/validation.md: no section names its `make validate CONFIG=... N=... SIZE=...` command")
    # a broken promise exits 1 and is a result the section reports (compact_narrow_s2's is): "-", the job goes on;
    # a command that fails otherwise leaves its section's stamp stale, and so marked
    return tuple(f"-{c}" for c in cmds)


# full does not fit the 85F: its runs exit 1 and write that report (the "-" of a make recipe: the job goes on)
FPGA = tuple(f"{'-' if c == 'full' else ''}make fpga CONFIG={c}{x}" for c in ("full", "reduced", "compact")
             for x in (" FPGA_REGS=0", "")) + \
    tuple(f"make fpga CONFIG={c} {x}" for c in ("reduced", "compact") for x in ("SEED=2", "SEED=3", "DSP_REGS=0"))


def jobs() -> list[Job]:
    """Every job, in no particular order (run() orders them)."""
    v = "verification.md"
    return [
        Job("synth", ("synthesis.md", None), ("make synth",), 25),
        Job("frames", ("conformance.md", None), ("make frames",), 10),
        Job("formal", (v, "Formal"), ("make formal",), 10),
        # mutants and explore: measured (docs/verification.md: 87 min of mutants with an empty cache; stop 48: explore's
        # 69 points in 41 min on two workers from empty block and truth caches, their own time 64 min; stop 44's
        # estimate of 6 hours came from 4 points under load; a point already in explore/points/ costs nothing)
        Job("mutants", (v, "Mutants"), ("make mutants N=100 SEED=1 JOBS=1",), 90),
        # gls: the named three about 70 min (full's netlist alone about an hour), the six others 2 to 12 min each
        # (stop 50: compact_sat2 7 min; compact_fpga's quadric, its multipliers pipelined, 10 min of synthesis alone)
        Job("gls", (v, "Gate-level simulation"), tuple(f"make gls CONFIG={c}" for c in GLS_CONFIGS), 105),
        Job("coverage", (v, "Coverage"), ("make coverage JOBS=1",), 13),
        Job("fpga", ("fpga.md", None), FPGA, 25),
        Job("explore", ("tradeoffs.md", None), ("make explore JOBS=1",), 70),
        Job("filters", ("filters.md", None), (_filters_command(),), 25, after=("explore",)),
        Job("precision", ("precision.md", None), ("make precision PRECISION_SIZE=512",), 10),
        Job("renders", ("scenes.md", None), ("make renders",), 10),
        Job("animation", ("animation.md", None), _animation_commands(), 15),
        Job("validate", ("validation.md", None), _validate_commands(), 60),
    ]


def stamped_sections() -> dict[tuple[str, str | None], dict]:
    """{(doc under docs/, section or None): its stamp} of every stamp in docs/: a doc with several
    stamps has one a `## ` section (the heading above the stamp), a doc with one stamp is whole."""
    out = {}
    for p in sorted(DOCS.rglob("*.md")):
        lines = p.read_text().splitlines()
        stamps = [i for i, x in enumerate(lines) if x.startswith(STAMP)]
        for i in stamps:
            title = None
            if len(stamps) > 1:
                title = next((lines[k][3:].strip() for k in range(i, -1, -1) if lines[k].startswith("## ")), None)
            out[(str(p.relative_to(DOCS)), title)] = read_stamp(lines[i])
    return out


def is_stale(stamp: dict) -> bool:
    """A stamp naming another rtl/ or another configuration (by its keys' hash) than today's."""
    if stamp.get("rtl") not in (None, rtl_source_hash()):
        return True
    return bool(_changed(stamp))


def _changed(stamp: dict) -> list[tuple[str, str, str]]:
    """[(name, stamped hash, today's)] of the stamp's configurations (config/ and config/candidates/:
    model.hw.config.stamped_config) that changed since."""
    now = {k: config_hash(c) for k in stamp if k != "rtl" and (c := stamped_config(k)) is not None}
    return [(k, stamp[k], n) for k, n in now.items() if n != stamp[k]]


def _section_span(lines: list[str], title: str | None) -> tuple[int, int]:
    """(index of the section's heading line, end index) in a doc's lines: the `# ` title and the
    whole doc for None, else the `## title` heading up to the next `## ` heading."""
    if title is None:
        return next((i for i, x in enumerate(lines) if x.startswith("# ")), 0), len(lines)
    i = lines.index(f"## {title}")
    return i, next((k for k in range(i + 1, len(lines)) if lines[k].startswith("## ")), len(lines))


def banner_text(stamp: dict, commands: tuple[str, ...]) -> str:
    """The line a stale section carries under its heading: what it was measured on, what is there now."""
    now = rtl_source_hash()
    what = []
    if stamp.get("rtl") not in (None, now):
        what.append(f"rtl/ {stamp['rtl']}, now {now}")
    what += [f"{k} {h}, now {n}" for k, h, n in _changed(stamp)]
    cmd = commands[0] + (f" and {len(commands) - 1} more" if len(commands) > 1 else "")
    return (f"{BANNER} the figures below were measured on another source than today's ({'; '.join(what)}); "
            f"`make regen` reruns them (`{cmd}`).")


def banners() -> dict[tuple[str, str | None], str]:
    """{(doc, section): its stale banner line} of every section that carries one."""
    out = {}
    for (doc, title) in stamped_sections():
        lines = (DOCS / doc).read_text().splitlines()
        a, b = _section_span(lines, title)
        for x in lines[a:b]:
            if x.startswith(BANNER):
                out[(doc, title)] = x
    return out


def mark() -> list[tuple[str, str | None]]:
    """Give every stale stamped section its banner (under its heading) and take it from every
    other: nothing stale looks current. -> the stale sections."""
    cmds = {j.section: j.commands for j in jobs()}
    stale = []
    for (doc, title), stamp in stamped_sections().items():
        p = DOCS / doc
        lines = p.read_text().splitlines()
        a, b = _section_span(lines, title)
        body = lines[a + 1:b]
        if body[:1] == [""] and body[1:2] and body[1].startswith(BANNER):  # the mark: a blank line and the banner
            body = body[2:]
        if is_stale(stamp):
            stale.append((doc, title))
            body = ["", banner_text(stamp, cmds.get((doc, title), ("make regen",)))] + body
        new = lines[:a + 1] + body + lines[b:]
        if new != lines:
            p.write_text("\n".join(new) + "\n")
    return stale


def plan(all_: bool = False, only: list[str] | None = None) -> list[Job]:
    """The jobs to run: those of stale sections (or every job: all_; or the named ones: only), the
    longest first, each after the jobs it waits for."""
    js = {j.name: j for j in jobs()}
    if only:
        unknown = [n for n in only if n not in js]
        if unknown:
            raise UserError(f"--only {','.join(only)}: no job {unknown[0]} (known: {', '.join(js)})")
        chosen = [js[n] for n in only]
    else:
        secs = stamped_sections()
        chosen = [j for j in js.values() if all_ or (j.section in secs and is_stale(secs[j.section]))]
    return sorted(chosen, key=lambda j: -j.minutes)


def run(todo: list[Job], lanes: int, progress: bool = True, logs=LOGS) -> list[dict]:
    """Run the jobs on `lanes` threads, each job's commands one after another in ROOT (a failed
    command ends its job), its output in logs/<job>.log; a job waits for the chosen jobs in its
    `after`. -> one result a job, in todo's order: {job, rc, failed (the command), minutes, start, end}."""
    logs.mkdir(parents=True, exist_ok=True)
    names = {j.name for j in todo}
    done: dict[str, dict] = {}
    lock = threading.Condition()
    queue = list(todo)
    bar = progress_bar(progress, total=len(todo), desc="regen", unit="job", leave=True)

    def take():
        with lock:
            while True:
                ready = [j for j in queue if all(a in done or a not in names for a in j.after)]
                if ready:
                    queue.remove(ready[0])
                    return ready[0]
                if not queue:
                    return None
                lock.wait()

    def lane():
        while (j := take()) is not None:
            t0, rc, failed = time.time(), 0, ""
            with open(logs / f"{j.name}.log", "w") as log:
                for c in j.commands:
                    log.write(f"$ {c}\n")
                    log.flush()
                    rc = subprocess.run(shlex.split(c.lstrip("-")), cwd=ROOT, stdout=log, stderr=subprocess.STDOUT).returncode
                    if rc and c.startswith("-"):  # an exit status that is a result (make's "-"): noted, not a failure
                        log.write(f"(exit {rc}, expected: the job goes on)\n")
                        rc = 0
                    elif rc:
                        failed = c
                        break
            with lock:
                t1 = time.time()
                done[j.name] = {"job": j.name, "rc": rc, "failed": failed, "minutes": round((t1 - t0) / 60, 1),
                                "start": t0, "end": t1}
                bar.update(1)
                bar.set_postfix_str(f"{j.name} {'ok' if not rc else 'FAILED'}")
                lock.notify_all()

    threads = [threading.Thread(target=lane) for _ in range(lanes)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    bar.close()
    return [done[j.name] for j in todo]


def main(argv=None) -> int:
    ap = Parser(prog="regen", description=__doc__.splitlines()[0])
    ap.add_argument("--all", action="store_true", help="every job, not only those of stale sections")
    ap.add_argument("--only", help="these jobs only (comma-separated names)")
    ap.add_argument("--jobs", type=int, default=2, help="lanes at once, 1..8 (default 2)")
    ap.add_argument("--dry-run", action="store_true", help="print the plan, run nothing")
    ap.add_argument("--mark", action="store_true",
                    help="run nothing: mark each stale section as stale under its heading, unmark the others")
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)

    def go():
        check_range("--jobs", a.jobs, 1, 8)
        if a.mark:
            left = mark()
            print(f"regen: {len(left)} stale section(s) marked" + (": " + ", ".join(
                f"docs/{d}{f' ({s})' if s else ''}" for d, s in left) if left else ""))
            return 0
        todo = plan(a.all, [x for x in a.only.split(",") if x] if a.only else None)
        for j in todo:
            doc, sec = j.section
            print(f"{j.name:10s} ~{j.minutes:4.0f} min  docs/{doc}{f' ({sec})' if sec else ''}: " + "; ".join(j.commands))
        if not todo:
            print("regen: every stamped section names today's rtl/ and configurations: nothing to run")
        if a.dry_run or not todo:
            return 0
        res = run(todo, a.jobs, progress=not a.quiet)
        for r in res:
            print(f"{r['job']:10s} {r['minutes']:6.1f} min  " + ("ok" if not r["rc"] else
                  f"FAILED (exit {r['rc']}: {r['failed']}; out/regen/{r['job']}.log)"))
        left = [f"docs/{d}{f' ({s})' if s else ''}" for d, s in mark()]
        if left:
            print("regen: still stale (each marked so under its heading): " + ", ".join(left), file=sys.stderr)
        return 1 if left or any(r["rc"] for r in res) else 0

    return run_main("regen", go)


if __name__ == "__main__":
    sys.exit(main())
