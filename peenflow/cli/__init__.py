"""The ``peenflow`` command: one verb per module.

    peenflow run STUDY [--until STAGE] [--dry-run] [--workers N] [--scheduler ADDR] [--store PATH]
    peenflow status STUDY [--why]
    peenflow rerun STUDY STAGE
    peenflow show STUDY STAGE
    peenflow report STUDY
    peenflow check STUDY
    peenflow clean STUDY [--dry-run]
    peenflow unlock STUDY [KEY ... | --all]
    peenflow intensity STRIPS.csv --strip {N,A,C}
    peenflow --version
"""

from __future__ import annotations

import argparse
import sys

from . import check, clean, intensity, report, rerun, run, show, status, unlock

VERBS = [run, status, rerun, show, report, check, clean, unlock, intensity]


def build_parser() -> argparse.ArgumentParser:
    from .. import __version__

    parser = argparse.ArgumentParser(prog="peenflow", description=__doc__.split("\n")[0])
    parser.add_argument("--version", action="version", version=f"peenflow {__version__}")
    sub = parser.add_subparsers(dest="verb", required=True, metavar="VERB")
    for verb in VERBS:
        p = sub.add_parser(verb.NAME, help=verb.HELP, description=verb.__doc__)
        verb.add_arguments(p)
        p.set_defaults(handler=verb.main)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    from ._common import UserError

    try:
        return int(args.handler(args) or 0)
    except UserError as exc:
        print(f"peenflow {args.verb}: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # the environment: read-only or full disk, a path that is a file, ...
        if isinstance(exc, BrokenPipeError):
            return 0
        where = f" ({exc.filename})" if getattr(exc, "filename", None) else ""
        print(f"peenflow {args.verb}: {exc.strerror or exc}{where}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into `head`
        return 0
    except KeyboardInterrupt:
        print("\ninterrupted: finished results are kept; rerun to resume", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
