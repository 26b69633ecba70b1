"""igms-sweep SPEC.yaml --out DIR [--address ADDR] [--workers N]: a sweep spec run on Ray (igms.sweeps),
its rows in DIR/results.parquet."""
import argparse
import os
import sys

from .sweep_spec import SpecError


def main(argv=None):
    parser = argparse.ArgumentParser(prog="igms-sweep", description=__doc__.split("\n\n")[0])
    parser.add_argument("spec", help="the sweep spec (YAML): scene, script, seconds, grid or random, metrics")
    parser.add_argument("--out", required=True, help="folder for results.parquet (a rerun skips the runs in it)")
    parser.add_argument("--address", help="a Ray cluster's address (default: a local cluster, started and stopped)")
    parser.add_argument("--workers", type=int, help="CPUs of the local cluster (default: all)")
    parser.add_argument("--serial", action="store_true", help="run in this process, without Ray")
    parser.add_argument("--retry-failed", action="store_true", help="run again the runs that recorded an error")
    parser.add_argument("--working-dir", help="a folder Ray ships to every worker (the scene's files, on a cluster)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be >= 1")
    from .sweeps import RESULTS, run_sweep
    try:
        rows = run_sweep(args.spec, args.out, address=args.address, workers=args.workers,
                         progress=not args.no_progress, serial=args.serial, retry_failed=args.retry_failed,
                         working_dir=args.working_dir)
    except (SpecError, OSError) as e:
        print(f"igms-sweep: {e}", file=sys.stderr)
        return 2
    failed = int(rows["error"].notna().sum())
    print(f"igms-sweep: {len(rows)} runs in {args.out}/{RESULTS}, {failed} failed")
    return 0


def run():
    """The program: main(), then out without the interpreter's teardown. pyarrow's threads can still be
    running then and abort the process after a finished sweep ("terminate called without an active
    exception", apache/arrow#34314; 1 to 4 of 40 runs of a 9-run serial sweep here under load)."""
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    run()
