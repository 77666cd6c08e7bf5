"""What app's commands share and nothing below them needs: the truth's sampling flags
(render, animation) and the provenance of a run (`git_describe`). The one-line errors, the
staged outputs and the progress bar are model.cli's, shared with sim, synth and explore."""
from __future__ import annotations

import subprocess

from model.cli import check_range
from model.hw.config import ROOT


def add_truth_args(ap, ss: int, band_ss: int) -> None:
    """--truth-ss and --band-ss (model.scene.truth: samples a pixel axis outside / inside the
    tiles of the band where the filter width exceeds N/8 entries); check_truth_args checks them."""
    ap.add_argument("--truth-ss", type=int, default=ss, help=f"truth samples a pixel axis, 1..64 (default {ss})")
    ap.add_argument("--band-ss", type=int, default=band_ss,
                    help=f"truth samples a pixel axis in the tiles with filter width > N/8, 1..64 (default {band_ss})")


def check_truth_args(a) -> None:
    check_range("--truth-ss", a.truth_ss, 1, 64)
    check_range("--band-ss", a.band_ss, 1, 64)


def git_describe() -> str:
    """`git describe --always --dirty` of the repository, or "unknown"."""
    try:
        return subprocess.run(["git", "-C", str(ROOT), "describe", "--always", "--dirty"], capture_output=True,
                              text=True, timeout=10).stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


VERIFICATION_DOC = ROOT / "docs" / "verification.md"


def write_doc_section(title: str, body: str, path=VERIFICATION_DOC) -> None:
    """Replace the section `## <title>` of a doc shared by several commands (docs/verification.md:
    formal, gate-level simulation, coverage, mutants), from its heading to the next `## ` heading,
    with `body` (appended when the doc has no such section; the doc is created when missing). The
    other sections are left as they are."""
    from pathlib import Path

    path = Path(path)
    head = f"## {title}"
    text = path.read_text() if path.exists() else "# Verification beyond random vectors\n"
    lines = text.rstrip("\n").split("\n")
    new = [head, "", *body.strip("\n").split("\n")]
    if head in lines:
        i = lines.index(head)
        j = next((k for k in range(i + 1, len(lines)) if lines[k].startswith("## ")), len(lines))
        lines[i:j] = new + ([""] if j < len(lines) else [])
    else:
        lines += ["", *new]
    path.write_text("\n".join(lines) + "\n")
