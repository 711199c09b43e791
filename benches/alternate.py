#!/usr/bin/env python3
"""Two or more rtlang builds timed against each other in one run.

The machine's speed drifts between minutes, so builds are compared by
running them alternately on the same arguments: every round runs each build
once, in the order given. Prints each run's samples/s (the render time
rtlang prints, scene parse and build excluded) and user CPU seconds, then per
build the median rate, its ratio to the first build's median, and in how many
rounds it was faster than the first build.

    python3 benches/alternate.py --rounds 6 OLD NEW -- render scenes/spheres.rt \\
        --width 400 --height 225 --spp 64 --integrator path --seed 1 -o /tmp/s.png

Not part of CI: it measures time.
"""

import argparse
import re
import resource
import statistics
import subprocess
import sys

RATE = re.compile(r"([\d.]+) M samples/s")


def run(binary, args):
    """(M samples/s, user CPU seconds) of one run of `binary args`."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
    try:
        done = subprocess.run([binary, *args, "--progress", "none"], capture_output=True, text=True)
    except OSError as e:
        sys.exit(f"cannot run {binary}: {e}")
    user = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - before
    text = done.stdout + done.stderr
    rate = RATE.search(text)
    if done.returncode != 0 or rate is None:
        sys.exit(f"{binary} {' '.join(args)} failed (exit {done.returncode}):\n{text}")
    return float(rate.group(1)), user


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        usage="%(prog)s [--rounds N] BUILD BUILD [BUILD ...] -- RTLANG_ARGS ...")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("builds", nargs="+", help="rtlang binaries; the first is the baseline")
    argv = sys.argv[1:]
    cut = argv.index("--") if "--" in argv else len(argv)
    opts = parser.parse_args(argv[:cut])
    args = argv[cut + 1:]
    if len(opts.builds) < 2 or not args or opts.rounds < 1:
        parser.error("give two or more builds, at least one round, then -- and rtlang's arguments")

    rates = {b: [] for b in opts.builds}
    print("| round | " + " | ".join(opts.builds) + " |  (M samples/s, user s)")
    for r in range(1, opts.rounds + 1):
        cells = []
        for b in opts.builds:
            rate, user = run(b, args)
            rates[b].append(rate)
            cells.append(f"{rate:.3f} ({user:.2f} s)")
        print(f"| {r} | " + " | ".join(cells) + " |", flush=True)

    base = opts.builds[0]
    base_median = statistics.median(rates[base])
    for b in opts.builds:
        median = statistics.median(rates[b])
        wins = sum(x > y for x, y in zip(rates[b], rates[base]))
        print(f"{b}: median {median:.3f} M samples/s ({min(rates[b]):.3f}-{max(rates[b]):.3f}), "
              f"{median / base_median:.3f}x {base}, faster in {wins} of {opts.rounds} rounds")


if __name__ == "__main__":
    main()
