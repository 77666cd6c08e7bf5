"""`python -m model.scene COMMAND ...`: the scene front end's commands.

    python -m model.scene needs SCENE [--size 256] [--json]   what a scene needs of the hardware
"""
from __future__ import annotations

import sys

COMMANDS = {"needs": "model.scene.needs"}


def main(argv=None) -> int:
    import importlib

    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] not in COMMANDS:
        got = f"'{argv[0]}'" if argv else "nothing"
        print(f"model.scene: expected a command ({', '.join(COMMANDS)}), got {got}", file=sys.stderr)
        return 2
    return importlib.import_module(COMMANDS[argv[0]]).main(argv[1:])


if __name__ == "__main__":
    sys.exit(main())
