"""The one error path and the one output discipline of every command, in the lowest layer that
has one (`python -m app.render`, `python -m sim.frame`, `python -m explore.sweep`, `python -m
synth.fpga`, ...; make render / frame / explore / fpga), and the progress bar they share
(`progress_bar`, also the truth's, model.scene.truth).

Errors: every input problem -- a bad scene file (SceneError), configuration (ConfigError), a
value that does not fit the hardware (FormatError), a bad argument, path or missing tool
(UserError), a file that cannot be read or written (OSError) -- is printed as ONE line on
stderr, ``<command>: <file or flag>: <key>: <what was expected>, got <what was found>``, and
the command exits with status 2, no traceback (`run_main`). Everything that can be known
before a simulation starts is checked before it starts.

Outputs: a run writes into a fresh temporary directory beside its target
(``<target>.tmp-<pid>-...``, `staged`), and only a run that has completed is moved into place
(the earlier target removed first). A failed run leaves no partial output, and the target's
earlier contents are replaced by a report.json ``{"status": "failed", "error": ...}`` so that
nothing stale looks current.
"""
from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
import sys
import tempfile
from pathlib import Path

from model.hw.config import CONFIG_NAMES, ConfigError
from model.hw.quantize import FormatError


class UserError(ValueError):
    """A bad argument, path or missing tool (one-line message)."""


def input_errors():
    """The exception classes that are the user's input, not a bug (exit status 2)."""
    from model.scene.scene import SceneError

    return (SceneError, ConfigError, FormatError, UserError, OSError)


class Parser(argparse.ArgumentParser):
    """argparse with one-line errors (prog: message), exit status 2."""

    def error(self, message):
        print(f"{self.prog}: {' '.join(message.split())}", file=sys.stderr)
        sys.exit(2)


def run_main(prog: str, fn) -> int:
    """fn() -> exit status, with every input error as one line on stderr and status 2."""
    try:
        return fn()
    except input_errors() as e:
        msg = " ".join(str(e).split())
        print(msg if msg.startswith(prog + ":") else f"{prog}: {msg}", file=sys.stderr)
        return 2


def check_range(flag: str, value: int, lo: int, hi: int, why: str = "") -> int:
    if not lo <= value <= hi:
        raise UserError(f"{flag} {value}: expected {lo}..{hi}{' (' + why + ')' if why else ''}")
    return value


def check_config(name: str) -> str:
    """--config: a configuration of config/ (the named ones, or a variant file such as full_fc),
    or the path of a configuration file (a .toml: make fit's answer, out/fit/<name>.toml)."""
    from model.hw.config import config_file_names, is_config_file, load_config

    if name.endswith(".toml") or os.sep in name:
        if not Path(name).is_file():
            raise UserError(f"--config {name}: no such configuration file")
        try:
            load_config(name)
        except ConfigError as e:
            raise UserError(f"--config {name}: {e}") from None
        return name
    if name not in CONFIG_NAMES and not is_config_file(name):
        raise UserError(f"--config {name}: no such configuration (known: {', '.join(config_file_names())})")
    return name


def config_label(arg: str) -> str:
    """The name a --config argument's outputs go under: the name itself, or a file's stem."""
    return Path(arg).stem if arg.endswith(".toml") or os.sep in arg else arg


def resolve_scene(arg: str) -> tuple[str, Path]:
    """--scene: a built-in scene name (scenes/<name>.toml) or a path to a .toml file.
    -> (name used for the output directory: the file's stem, path)."""
    from model.scene.passes import SCENE_DIR, SCENES

    p = Path(arg)
    if p.suffix == ".toml" or os.sep in arg:
        if p.suffix != ".toml":
            raise UserError(f"--scene {arg}: expected a scene name ({', '.join(SCENES)}) or a path to a .toml file")
        if not p.is_file():
            raise UserError(f"--scene {arg}: no such scene file")
        return p.stem, p
    p = SCENE_DIR / f"{arg}.toml"
    if not p.is_file():
        raise UserError(f"--scene {arg}: no such scene (known: {', '.join(SCENES)}; or a path to a .toml file)")
    return arg, p


def _failed_report(target: Path, error: str, command: str) -> None:
    """Replace the target's earlier contents by a failure report (nothing stale stays)."""
    try:
        if target.is_dir():
            shutil.rmtree(target)
        elif target.exists():
            return  # not ours (a file where the directory should be): leave it
        target.mkdir(parents=True)
        (target / "report.json").write_text(json.dumps({"status": "failed", "error": error, "command": command},
                                                       indent=2) + "\n")
    except OSError:
        pass


@contextlib.contextmanager
def staged(target: Path, command: str = ""):
    """Yield a fresh temporary directory beside `target`; on success it becomes `target`.

    The temporary directory is made first, so an output directory that cannot be written is
    found before any work (UserError). On any exception the temporary directory is removed,
    the target marked failed (_failed_report) and the exception passes on."""
    target = Path(target)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.tmp-{os.getpid()}-", dir=target.parent))
    except OSError as e:
        raise UserError(f"{target}: cannot write the output directory: {e.strerror or e}") from None
    try:
        yield tmp
        if target.is_dir():
            old = Path(tempfile.mkdtemp(prefix=f".{target.name}.old-", dir=target.parent))
            target.rename(old / "x")
            shutil.rmtree(old)
        elif target.exists():
            raise UserError(f"{target}: exists and is not a directory")
        tmp.rename(target)
    except BaseException as e:
        shutil.rmtree(tmp, ignore_errors=True)
        _failed_report(target, " ".join(str(e).split()) or type(e).__name__, command)
        raise


def memory_available() -> int | None:
    """MemAvailable in bytes (Linux), or None."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def progress_bar(progress: bool, total: int | None = None, desc: str = "", unit: str = "step", iterable=None, **kw):
    """The progress bar of every command: tqdm on stderr (update(n), close(), set_postfix, a
    context manager, or wrapping `iterable`) that leaves no line behind unless kw says leave=True;
    when not `progress`, one that shows nothing. kw: tqdm's other arguments (initial, ...)."""
    from tqdm import tqdm

    return tqdm(iterable, total=total, desc=desc, unit=unit, file=sys.stderr, disable=not progress,
                **{"leave": False, **kw})
