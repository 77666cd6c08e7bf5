"""`python -m app COMMAND ...`: the command layer's commands, each also `python -m app.COMMAND`.

    python -m app needs SCENE [--size 256] [--json]          what a scene needs of the hardware
    python -m app render --scene zone_plate --config full     (make render, make renders)
    python -m app animation --scene seascape [--rtl]          (make animation)
    python -m app precision --size 512                        (make precision)
    python -m app quality --config compact --step KEY=VALUE   the PSNR behind a configuration's widths
"""
from __future__ import annotations

import sys

COMMANDS = ("needs", "render", "animation", "precision", "quality")


def main(argv=None) -> int:
    import importlib

    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in COMMANDS:
        got = f"'{argv[0]}'" if argv else "nothing"
        print(f"app: expected a command ({', '.join(COMMANDS)}), got {got}", file=sys.stderr)
        return 2
    return importlib.import_module(f"app.{argv[0]}").main(argv[1:])


if __name__ == "__main__":
    sys.exit(main())
