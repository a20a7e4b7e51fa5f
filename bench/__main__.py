"""``python -m bench [--quick] [NAME ...]``: run benchmark groups, one JSON line per figure."""

from __future__ import annotations

import argparse
import importlib
import sys
import traceback

GROUPS = ("cli", "render", "retarget", "pipeline", "track", "face", "read", "fidelity", "predict", "live", "stream",
          "batch", "bridge", "lipsync", "physics", "room", "life", "scale")
#: Groups run only when named: they take minutes.
LONG = ("soak",)


def main(argv: list[str] | None = None) -> int:
    """Run the named groups (all by default); returns the exit status."""
    parser = argparse.ArgumentParser(prog="python -m bench", description=__doc__)
    parser.add_argument("names", nargs="*", metavar="NAME",
                        help=f"groups to run: {', '.join(GROUPS)} (default: all of these), or {', '.join(LONG)} "
                             "(10 minutes; only when named)")
    parser.add_argument("--quick", action="store_true", help="fewer frames and repeats (a smoke test, not a measure)")
    args = parser.parse_args(argv)
    unknown = [n for n in args.names if n not in GROUPS + LONG]
    if unknown:
        parser.error(f"unknown benchmark group(s) {unknown}; known: {', '.join(GROUPS + LONG)}")
    failed = []
    for name in args.names or GROUPS:
        try:  # a group that fails is said and the others still run; the exit status says it failed
            for figure in importlib.import_module(f"bench.{name}").run(quick=args.quick):
                print(figure.to_json(), flush=True)
        except Exception:  # noqa: BLE001 - any failure of a group is reported, with its traceback
            failed.append(name)
            print(f"bench: group {name} failed:\n{traceback.format_exc()}", file=sys.stderr, flush=True)
    if failed:
        print(f"bench: {len(failed)} group(s) failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
