"""The ``neurov`` command line."""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Sequence

__all__ = ["main"]

# Each command's modules are imported inside main() once the command is
# chosen (deferred on purpose): `neurov --help`, `--version` and a bad command
# line answer without loading the runs, Matplotlib, pandas, SciPy or Optuna.

# The numbers are neurov.running.command.EXIT_DIVERGED and its neighbours; written out
# here so that --help answers without importing numpy.
_EXIT_STATUS = """exit status:
  0    success
  1    error: a bad file or argument, an output folder that cannot be written
  2    bad command line
  3    a run diverged (neurov run, neurov paper); everything simulated is
       still written and the metrics cover it. neurov tune: a controller
       is not tuned (no trial feasible, or every run failed); every file
       is still written, best.toml with the least bad gains
  130  interrupted (Ctrl-C)
  143  stopped by SIGTERM (neurov study, neurov tune)

documentation: docs/running.md (running a scenario: outputs, metrics window,
divergence, long runs)"""


def _shipped_studies() -> str:
    """The shipped study files by name, read from the package folder (the
    study package itself imports numpy)."""
    from importlib.resources import files

    return ", ".join(sorted(p.name[:-5] for p in (files("neurov") / "studies").iterdir()
                            if p.name.endswith(".toml")))


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="neurov",
        description="Adaptive neural-network control for underwater vehicles: run the paper's "
        "experiments or your own scenarios.",
        epilog=_EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="store_true", help="print the version and exit")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    paper = sub.add_parser(
        "paper",
        help="reproduce the paper's Figs. 3-5",
        description="Runs the paper's experiments (NEROV, 5 Hz, RBF network with width 30 and "
        "gain 0.3) and writes fig3_xy.png, fig4_inputs.png, fig5_yaw_disturbance.png, "
        "metrics.json and summary.md. See docs/paper-reproduction.md.",
        epilog=_EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    paper.add_argument("--out", default="paper-results", metavar="DIR",
                       help="output folder (default: paper-results)")

    run = sub.add_parser(
        "run",
        help="run a scenario file",
        description="Runs one scenario file (TOML; the format and the shipped examples are in "
        "docs/running.md), prints its metrics over t >= 10 s (the start-up transient skipped; "
        "half the run if it is shorter than 20 s), and with --out writes result.csv, result.npz, "
        "metrics.json and scenario.toml (a copy of the scenario file; neurov.load_result reads the "
        "folder back). A run that diverges still writes everything it simulated and exits "
        "with status 3.",
        epilog=_EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    run.add_argument("scenario", metavar="SCENARIO.toml",
                     help="the scenario file, or a shipped scenario's name (e.g. paper_fig3)")
    run.add_argument("--out", default=None, metavar="DIR", help="folder for the results")
    run.add_argument("--plot", action="store_true", help="also write PNG figures (needs --out)")
    run.add_argument("--format", choices=("csv", "mcap"), default="csv", dest="file_format",
                     help="the rows as result.csv, or as result.mcap: a ROS 2 recording for Foxglove, "
                     "PlotJuggler and ros2 bag (needs neurov[ros]; docs/recordings.md)")
    run.set_defaults(usage_of=run)  # a bad combination of options is told with run's usage

    study = sub.add_parser(
        "study",
        help="run a study: every scenario x controller x perturbed plant",
        description="Runs every (scenario x controller x sample) of a study file (TOML; see "
        "docs/studies.md) and writes runs.csv (one row per run), summary.csv, league.md and "
        "plots. Runs already in DIR are not redone. Shipped studies by name: "
        + _shipped_studies() + ".",
    )
    study.add_argument("study", metavar="STUDY.toml", help="the study file, or a shipped study's name")
    study.add_argument("--out", default=None, metavar="DIR", help="output folder (default: study-NAME)")
    study.add_argument("--workers", type=int, default=None, metavar="N",
                       help="worker processes (default: one per core)")
    study.add_argument("--scheduler", default=None, metavar="ADDRESS",
                       help="run on the existing Dask cluster at ADDRESS (e.g. tcp://host:8786)")
    study.add_argument("--executor", choices=("auto", "dask", "processes"), default="auto",
                       help="dask, local processes, or auto: Dask if installed (default)")
    study.add_argument("--batch-size", type=int, default=None, metavar="N",
                       help="runs per task (default: chosen from the number of runs and workers)")
    study.add_argument("--format", choices=("csv", "parquet"), default="csv", dest="table_format",
                       help="format of the runs table (parquet needs pyarrow)")
    study.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    study.add_argument("--quiet", action="store_true",
                       help="no progress bars (there are none either when stderr is not a terminal)")
    study.set_defaults(usage_of=study)

    report = sub.add_parser(
        "report",
        help="print a study folder's tables as Markdown (runs nothing)",
        description="Prints a table of a study folder (written by 'neurov study', or a tuning's verdict "
        "folder) as Markdown: medians (controllers by mean rank against the scenarios), overall (mean "
        "rank, first places, failure rate), verdict (the verdict in words), league (league.md), timing (runs and time, from timing.json), versus (one controller against others on the same plants) "
        "or failed (the failed runs per scenario and controller, and how far they ran away). It "
        "refuses a folder whose runs are of another version of the study. The docs' tables are "
        "printed so (docs/studies.md).",
    )
    report.add_argument("folder", metavar="DIR", help="the study folder (study.json and runs.csv[.gz]), or a "
                        "tuning's folder (its verdict's tables)")
    report.add_argument("--table", choices=("medians", "overall", "verdict", "league", "timing", "versus", "failed"),
                        default="league", help="which table (default: league)")
    report.add_argument("--versus", default=None, metavar="A,B[,C...]",
                        help="with --table versus: the controller, then those it is compared with")
    report.set_defaults(usage_of=report)
    report.add_argument("--study", default=None, metavar="STUDY.toml",
                        help="the study file (default: the shipped study of study.json's name, else its source)")

    view = sub.add_parser(
        "view",
        help="write a 3-D replay of runs as one HTML file (needs neurov[view])",
        description="Writes one self-contained HTML file (plotly.js inside: it opens offline) that "
        "replays runs in 3-D: the vehicle with its thrusters (or the applied force), the desired "
        "and the travelled path, the current and the waves at the vehicle, a time slider and "
        "play/pause. Several runs are drawn on one path to compare them. See docs/replay.md.",
    )
    view.add_argument("results", nargs="+", metavar="RESULT",
                      help="a run folder written by 'neurov run --out DIR', or a result file "
                      "(result.npz, .csv, .parquet or .mcap)")
    view.add_argument("--out", default="replay.html", metavar="FILE",
                      help="the HTML file to write (default: replay.html)")
    view.add_argument("--frames", type=int, default=None, metavar="N",
                      help="at most N frames (default: 150)")
    view.add_argument("--scenario", default=None, metavar="SCENARIO",
                      help="the runs' scenario (a file or a shipped name), for a result file with no "
                      "scenario.toml beside it")
    view.set_defaults(usage_of=view)

    from neurov.identification.cli import add_parser as add_identify

    add_identify(sub, _EXIT_STATUS)

    from neurov.pil.cli import add_parser as add_pil

    add_pil(sub, _EXIT_STATUS)

    tune = sub.add_parser(
        "tune",
        help="tune every controller of a tuning file with the same budget, then judge it on held-out plants",
        description="Tunes each controller of a tuning file (a study file with [tune] and per-controller "
        "search tables; see docs/tuning.md) with Optuna, its trials stored in DIR/tuning.db: a rerun "
        "resumes, and several processes given the same DIR share the budget. Writes trials.csv, "
        "best.toml, the figures and the verdict (DIR/verdict: a study of the tuned controllers on the "
        "test plants).",
    )
    tune.add_argument("tuning", metavar="TUNING.toml", help="the tuning file, or a shipped tuning's name")
    tune.add_argument("--out", default=None, metavar="DIR", help="output folder (default: tune-NAME)")
    tune.add_argument("--workers", type=int, default=None, metavar="N",
                      help="worker processes for a trial's runs (default: one per core)")
    tune.add_argument("--scheduler", default=None, metavar="ADDRESS",
                      help="run the trials' runs on the existing Dask cluster at ADDRESS")
    tune.add_argument("--only", action="append", default=None, metavar="CONTROLLER",
                      help="tune only this controller (repeatable; other processes may take the others)")
    tune.add_argument("--no-verdict", action="store_true", help="tune only, no study on the test plants")
    tune.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    tune.add_argument("--quiet", action="store_true", help="no progress bars")
    tune.add_argument("--seed", type=int, default=None, metavar="N",
                      help="the sampler's seed instead of the file's [tune] seed (a seed spread: one folder each)")
    table = sub.add_parser(
        "tune-table", help="print a Markdown table of tuning folders' outputs (budget, fronts, equal effort, "
        "seed spread)", description="Reads a tuning folder's budget.csv, pareto.csv, picks.csv or "
        "equal_effort.csv (or, for 'spread', several folders of one tuning with other seeds) and prints a "
        "Markdown table; it runs nothing.")
    table.add_argument("folders", nargs="+", metavar="DIR", help="tuning folder(s) (neurov tune --out)")
    table.add_argument("--table", required=True, choices=["budget", "fronts", "equal-effort", "spread"])

    params = sub.add_parser(
        "params",
        help="write the parameters of an ArduPilot log (.tlog, .bin) or parameter file as a .param file",
        description="Reads every parameter of a telemetry log (PARAM_VALUE), a DataFlash log (PARM) or a "
        "parameter file (QGroundControl or MAVProxy format) and writes them as a QGroundControl .param "
        "file; an [controller] type = \"ardusub\" scenario reads it with params = \"FILE\".",
    )
    params.add_argument("log", metavar="LOG", help="a .tlog, .bin, .param, .params or .parm file")
    params.add_argument("--out", default=None, metavar="FILE.param",
                        help="output file (default: LOG with the suffix .param)")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.version:
        from neurov import __version__

        print(f"neurov {__version__}")
        return 0
    if args.command is None:
        parser.print_help()
        return 2
    # Commands import lazily so that --help answers at once.
    try:
        if args.command == "paper":
            from neurov.paper.experiments import diverged_runs, run_paper
            from neurov.running.command import EXIT_DIVERGED

            bad = diverged_runs(run_paper(args.out))
            if bad:
                print(f"neurov: diverged: {', '.join(bad)} (exit status {EXIT_DIVERGED})", file=sys.stderr)
                return EXIT_DIVERGED
        elif args.command == "run":
            if args.plot and args.out is None:
                args.usage_of.error("--plot needs --out DIR")
            if args.file_format != "csv" and args.out is None:
                args.usage_of.error(f"--format {args.file_format} needs --out DIR")
            from neurov.errors import RefusedStepsWarning
            from neurov.running.command import EXIT_DIVERGED, refusal_message, run_scenario_file

            with warnings.catch_warnings():
                # Said below and in the printout, without a warning's source line.
                warnings.simplefilter("ignore", RefusedStepsWarning)
                result, metrics = run_scenario_file(args.scenario, out_dir=args.out, plot=args.plot,
                                                    file_format=args.file_format)
            if metrics["refused_steps"]:
                print(f"neurov: warning: {refusal_message(result, metrics)}", file=sys.stderr)
            if result.diverged:
                print(f"neurov: {result.divergence_message()} (exit status {EXIT_DIVERGED})", file=sys.stderr)
                return EXIT_DIVERGED
        elif args.command == "study":
            if args.workers is not None and args.workers < 1:
                args.usage_of.error("--workers must be >= 1")
            if args.batch_size is not None and args.batch_size < 1:
                args.usage_of.error("--batch-size must be >= 1")
            from neurov.study import main_study

            main_study(args.study, args.out, args.workers, args.scheduler, executor=args.executor,
                       table_format=args.table_format, plots=not args.no_plots,
                       batch_size=args.batch_size, quiet=args.quiet)
        elif args.command == "report":
            from neurov.study.markdown import main_report
            from neurov.tuning.folder import is_tuning_folder, verdict_of_folder

            folder, study = args.folder, args.study
            if study is None and is_tuning_folder(folder):
                folder, study = verdict_of_folder(folder)  # a tuning's folder: its verdict's tables
            versus = args.versus.split(",") if args.versus else None
            if (args.table == "versus") != (versus is not None):
                args.usage_of.error("--versus A,B[,...] goes with --table versus, and only with it")
            main_report(folder, args.table, study, versus)
        elif args.command == "view":
            if args.frames is not None and args.frames < 2:
                args.usage_of.error("--frames must be >= 2")
            from neurov.replay.command import main_view

            return main_view(args.results, args.out, args.frames, args.scenario)
        elif args.command == "identify":
            from neurov.identification.cli import run as run_identify

            return run_identify(args)
        elif args.command == "tune-table":
            from neurov.tuning.tables import main_table

            return main_table(args.folders, args.table)
        elif args.command == "pil":
            from neurov.pil.cli import run as run_pil

            return run_pil(args)
        elif args.command == "tune":
            if args.workers is not None and args.workers < 1:
                parser.error("--workers must be >= 1")
            from neurov.running.command import EXIT_DIVERGED
            from neurov.tuning import main_tune

            tuned = main_tune(args.tuning, args.out, args.workers, args.scheduler, verdict=not args.no_verdict,
                              plots=not args.no_plots, quiet=args.quiet, only=args.only, seed=args.seed)
            if tuned.unusable:
                return EXIT_DIVERGED
        elif args.command == "params":
            from neurov.laws.ardusub_params import write_log_parameters

            print(write_log_parameters(args.log, args.out))
    except KeyboardInterrupt as e:
        # A study says what it saved and that rerunning resumes; one line, no traceback.
        print(f"neurov: {str(e) or 'interrupted'}", file=sys.stderr)
        return 128 + int(getattr(e, "signum", 2))  # 130 for SIGINT, 143 for SIGTERM
    except (ValueError, OSError) as e:
        # ScenarioError and VehicleFileError are ValueErrors that name the
        # file and the field: the message is the whole story, no traceback.
        print(f"neurov: error: {e}", file=sys.stderr)
        return 1
    except MemoryError as e:
        # What neurov.memory could not foresee (a fit's working arrays, say): said, not a traceback.
        print(f"neurov: error: out of memory ({type(e).__name__}: {e or 'no message'}); the machine, or the "
              "process's address-space limit (ulimit -v), has too little for this input", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
