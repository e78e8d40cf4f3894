"""The ``hapex`` command line (contract in DESIGN.md).

::

    hapex run SCENARIO.yaml [--out DIR] [--seed N] [--set key.path=value ...] [--no-plots]
                            [--quick] [-v]
    hapex validate SCENARIO.yaml ...
    hapex list [scenarios|robots|kinds]
    hapex sweep SWEEP.yaml [--out DIR] [--jobs N] [--scheduler ADDR | --dask-local N] [--quick]
                           [--retry-failed]
    hapex reproduce [--quick] [--out DIR] [--only ID ...] [--jobs N]
    hapex --version

Exit codes: 0 success; 1 the scenario ran but its task failed; 2 bad input; 130 interrupted;
141 stdout closed early (``hapex list | head``). Errors are one line each on stderr,
``FILE:LINE: key.path: message``, all at once; no traceback unless -v.
"""

from __future__ import annotations

import argparse
import os
import signal
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path

from planner.exit_codes import (
    EXIT_BAD_INPUT,
    EXIT_BROKEN_PIPE,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
)


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit code 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        print(f"hapex: error: {message} (see 'hapex --help')", file=sys.stderr)
        raise SystemExit(EXIT_BAD_INPUT)


def _add_set_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="KEY.PATH=VALUE",
        help="override a scenario key (repeatable)",
    )


def _parser() -> argparse.ArgumentParser:
    from planner import __version__

    p = _Parser(
        prog="hapex",
        description="Haptic exploration of unknown objects: run "
        "scenario files, validate them, list what is bundled.",
    )
    p.add_argument("--version", action="version", version=f"hapex {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    r = sub.add_parser("run", help="run a scenario and write a run directory")
    r.add_argument("scenario", type=Path, help="scenario YAML file")
    r.add_argument(
        "--out",
        type=Path,
        default=None,
        help="run directory to write (default: runs/<name>-<timestamp>)",
    )
    r.add_argument("--seed", type=int, default=None, help="override the scenario's seed")
    _add_set_option(r)
    r.add_argument("--no-plots", action="store_true", help="do not draw figures")
    r.add_argument(
        "--quick",
        action="store_true",
        help="short smoke-test run (reduced horizons and resolutions)",
    )
    r.add_argument(
        "-v", "--verbose", action="store_true", help="progress messages, and tracebacks on errors"
    )

    v = sub.add_parser("validate", help="check scenario files without running them")
    v.add_argument("scenarios", type=Path, nargs="+", help="scenario YAML files")
    _add_set_option(v)
    v.add_argument("-v", "--verbose", action="store_true")

    ls = sub.add_parser("list", help="list bundled scenarios, robots, or scenario kinds")
    ls.add_argument(
        "what", nargs="?", default="scenarios", choices=("scenarios", "robots", "kinds")
    )
    ls.add_argument("-v", "--verbose", action="store_true")
    _sweep_parser(sub)
    from planner.reproduce.command import add_arguments as reproduce_arguments

    reproduce_arguments(
        sub.add_parser("reproduce", help="put every claim of the thesis beside hapex's result")
    )
    return p


def _sweep_parser(sub) -> None:
    """``hapex sweep``: its options live in :mod:`planner.sweep.command`."""
    from planner.sweep.command import add_arguments

    add_arguments(sub.add_parser("sweep", help="run a parameter study (many runs, resumable)"))


def _cmd_sweep(args) -> int:
    from planner.sweep.command import run_command

    return run_command(args)


def scenario_dirs() -> list[Path]:
    """Folders searched for bundled scenarios: ``./scenarios`` and the source tree's."""
    here = Path(__file__).resolve().parent.parent / "scenarios"
    out = []
    for d in (Path.cwd() / "scenarios", here):
        if d.is_dir() and d.resolve() not in [o.resolve() for o in out]:
            out.append(d)
    return out


def _print_issues(exc) -> None:
    for issue in exc.issues:
        print(str(issue), file=sys.stderr)


def _cmd_run(args) -> int:
    from planner.errors import InvalidParameter, ScenarioError
    from planner.results import run_directory_problem
    from planner.runner import execute
    from planner.scenario import late_issue, load_scenario

    if args.seed is not None and args.seed < 0:
        print(f"--seed: {args.seed}: must be >= 0", file=sys.stderr)
        return EXIT_BAD_INPUT
    problem = run_directory_problem(args.out) if args.out is not None else None
    if problem:  # checked before the run, not when its directory is written
        print(f"--out: {args.out}: {problem}", file=sys.stderr)
        return EXIT_BAD_INPUT
    config = load_scenario(args.scenario, args.overrides, seed=args.seed)
    try:
        outcome = execute(
            config,
            args.out,
            plots=not args.no_plots,
            quick=args.quick,
            base_dir=args.scenario.resolve().parent,
            verbose=args.verbose,
            progress=sys.stderr.isatty(),
        )
    except InvalidParameter as exc:  # bad input found late: put it at its key
        if args.verbose:
            traceback.print_exc()
        resolved = config.model_dump(mode="json")
        issue = late_issue(args.scenario, args.overrides, str(exc), args.seed, resolved)
        raise ScenarioError([issue]) from None
    res = outcome.result
    print(f"{config.name}: {res.status}{' - ' + res.reason if res.reason else ''}")
    print(f"run directory: {outcome.out_dir}")
    return EXIT_OK if res.status == "ok" else EXIT_FAILED


def _cmd_validate(args) -> int:
    from planner.errors import ScenarioError
    from planner.scenario import load_scenario

    bad = 0
    for path in args.scenarios:
        try:
            cfg = load_scenario(path, args.overrides)
        except ScenarioError as exc:
            _print_issues(exc)
            bad += 1
        else:
            print(f"{path}: ok ({cfg.kind})")
    return EXIT_BAD_INPUT if bad else EXIT_OK


def _cmd_list(args) -> int:
    if args.what == "kinds":
        from planner.scenario import kinds

        for name, spec in kinds().items():
            doc = (spec.config.__doc__ or "").strip().splitlines()
            print(f"{name:14s} {doc[0] if doc else ''}")
        return EXIT_OK
    if args.what == "robots":
        import robots

        catalogue = getattr(robots, "catalogue", None)
        if catalogue is None:
            print("no robot catalogue available in this installation", file=sys.stderr)
            return EXIT_FAILED
        for info in catalogue():
            print(f"{info.name}: {info.description}")
            for key, value in info.params.items():
                print(f"    {key} = {value}")
        return EXIT_OK
    from planner.errors import ScenarioError
    from planner.scenario import read_yaml

    rows = []
    for d in scenario_dirs():
        for path in sorted(d.glob("*.yaml")):
            try:
                data = read_yaml(path).data
            except ScenarioError:
                rows.append((path.stem, "?", "(unreadable)"))
                continue
            rows.append(
                (
                    str(data.get("name", path.stem)),
                    str(data.get("kind", "?")),
                    str(data.get("description", "")).strip().splitlines()[0]
                    if data.get("description")
                    else "",
                )
            )
    if not rows:
        print(
            "no bundled scenarios found (looked in ./scenarios and the source tree)",
            file=sys.stderr,
        )
        return EXIT_FAILED
    width = max(len(r[0]) for r in rows)
    kwidth = max(len(r[1]) for r in rows)
    for name, kind, desc in rows:
        print(f"{name:{width}s}  {kind:{kwidth}s}  {desc}")
    return EXIT_OK


def _dispatch(argv: Sequence[str] | None) -> int:
    args = _parser().parse_args(argv)
    from planner.errors import HapexError, ScenarioError

    verbose = getattr(args, "verbose", False)
    from planner.reproduce.command import run as _cmd_reproduce

    handlers = {
        "run": _cmd_run,
        "validate": _cmd_validate,
        "list": _cmd_list,
        "reproduce": _cmd_reproduce,
        "sweep": _cmd_sweep,
    }
    try:
        return handlers[args.command](args)
    except ScenarioError as exc:
        if verbose:
            traceback.print_exc()
        _print_issues(exc)
        return EXIT_BAD_INPUT
    except HapexError as exc:
        if verbose:
            traceback.print_exc()
        where = getattr(args, "scenario", None) or "hapex"
        print(f"{where}:0: (root): {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("interrupted; no run directory was written", file=sys.stderr)
        return EXIT_INTERRUPTED


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``hapex`` script. Returns the exit code.

    A reader that closes the pipe early (``hapex list kinds | head -1``) ends the command
    quietly with exit code 141 (128 + SIGPIPE, what the shell reports for ``yes | head``):
    the rest of the output is discarded, no traceback is printed.
    """
    os.environ.setdefault("MPLBACKEND", "Agg")
    try:
        try:
            return _dispatch(argv)
        finally:
            sys.stdout.flush()  # inside the try: a closed pipe fails here, not at exit
    except BrokenPipeError:
        # Python flushes stdout again at exit; point it at /dev/null so that flush is quiet.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return EXIT_BROKEN_PIPE


def entry() -> int:
    """The ``hapex`` console script: :func:`main`, then Ctrl-C is ignored while the
    interpreter exits. The command's work is done and its exit code decided; a SIGINT that
    arrived while Python joined worker threads or flushed files killed the process with the
    signal (exit -2 seen by the caller) after a sweep had finished and written everything."""
    code = main()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    return code


if __name__ == "__main__":  # pragma: no cover
    sys.exit(entry())
