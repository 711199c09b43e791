#!/usr/bin/env python3
"""Where each renderer spends a sample: every suite scene (benches/suite/)
rendered by rtlang and by its Mitsuba 3 twin under `perf record` (software
clock, two threads each), and the CPU time per sample split into
closest-hit tracing, shadow (any-hit) tracing and the rest (shading,
sampling, the film). The suite's ratios say how far apart the two are; this
says in which part.

rtlang's parts are its symbols: closest-hit tracing is every function of
`rtlang::geometry` but the any-hit walks and the `occluded` tests, which
are shadow tracing; the functions of the scene's parse, load and build
(named in `BUILD`) are left out, and the CPU time per sample is the
render's own (rtlang prints its rate). Where the compiler inlined an
any-hit walk into the integrator (the one-ray path of sets of spheres), it
counts as the rest; the analytic surface's shell walk serves both kinds
of ray and counts as closest-hit tracing. Mitsuba's parts are Embree's two
entry points (`intersect`, `occluded`) in `libembree3`; its shapes' own
tests called from Embree (the sphere's, for one) count as the rest, so its
tracing share is a lower bound. Mitsuba is profiled only while it renders
(`perf record --control`, switched on and off around the timed renders),
after a warm-up render that compiles its kernel.

Needs `perf`, `pip install mitsuba` and the suite's environment
(benches/suite/README.md).
"""

import argparse
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
FREQ = 4000  # perf samples per second of CPU time
ROW = re.compile(r"^\s*([\d.]+)%\s+(.*?)\s+\[[.k]\]\s+(.*?)\s*$")
# rtlang's functions that load and build the scene rather than render it.
BUILD = re.compile(r"sah::|::build|collapse|number_leaves|Packs<.*>::new|tobj|obj_lines|scene::obj|dec2flt"
                   r"|SplitWhitespace|rtlang::lang::|pest::|gen::|MeshData|tessellat")


def perf_rows(data):
    """(share %, dso, symbol) of every row of `perf report` on `data`."""
    out = subprocess.run(["perf", "report", "-i", str(data), "--no-children", "--stdio",
                          "--sort", "dso,symbol"], capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        m = ROW.match(line)
        if m:
            rows.append((float(m.group(1)), m.group(2), m.group(3)))
    return rows


def sample_count(data):
    """The number of samples `perf record` took into `data`."""
    out = subprocess.run(["perf", "report", "-i", str(data), "--stdio", "-n", "--sort", "dso"],
                         capture_output=True, text=True, check=True).stdout
    return sum(int(m.group(1)) for m in re.finditer(r"^\s*[\d.]+%\s+(\d+)\s", out, re.M))


def rtlang_parts(symbol):
    if BUILD.search(symbol):
        return None
    if "rtlang::geometry" not in symbol:
        return "rest"
    return "shadow" if ("walk_any" in symbol or "occluded" in symbol) else "closest"


def mitsuba_parts(dso, symbol):
    if dso.startswith("libembree"):
        if "::occluded" in symbol:
            return "shadow"
        if "::intersect" in symbol:
            return "closest"
        return "rest"
    if dso.startswith(("libLLVM", "libpython", "python")):
        return None
    return "rest"


def split(rows, parts):
    """Each part's share of the rows `parts` keeps (it returns None for the
    rows left out), as fractions of the kept rows."""
    shares = {"closest": 0.0, "shadow": 0.0, "rest": 0.0}
    for pct, dso, sym in rows:
        p = parts(dso, sym)
        if p is not None:
            shares[p] += pct
    kept = sum(shares.values())
    return {k: v / kept for k, v in shares.items()}, kept / 100.0


def profile(cmd, folder, name, control=()):
    data = pathlib.Path(folder) / f"{name}.data"
    done = subprocess.run(["perf", "record", "-q", "-e", "cpu-clock", "-F", str(FREQ), *control, "-o", str(data)]
                          + cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{done.stdout}{done.stderr}")
    return data, done.stdout + done.stderr


def mitsuba_child(args):
    """Renders the twin `--rounds` times after a warm-up, with perf's
    events on only for those renders (run under perf by the parent, whose
    control and acknowledgement fifos are `--fifos`)."""
    sys.path.insert(0, str(HERE))
    import suite as S  # noqa: E402  (sets Mitsuba's variant)
    import drjit as dr  # noqa: E402
    dr.set_thread_count(args.threads)
    mod = S.scene_modules(pathlib.Path(args.suite), f"^{args.child}$")[0]
    size = S.frame(mod, args.size)
    scene = S.load(mod, args.spp, size, args.sampler)
    S.mitsuba_render(scene, args.spp, 0)
    ctl, ack = args.fifos.split(",")
    with open(ctl, "w") as c, open(ack) as a:
        def command(word):
            c.write(word + "\n")
            c.flush()
            a.readline()
        command("enable")
        start = time.perf_counter()
        for k in range(args.rounds):
            S.mitsuba_render(scene, args.spp, k + 1)
        seconds = time.perf_counter() - start
        command("disable")
    print(f"rendered {seconds:.3f} s")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rtlang", default=None)
    ap.add_argument("--scenes", default=".", help="a regular expression the scene names must match")
    ap.add_argument("--suite", default=str(HERE.parent / "suite"))
    ap.add_argument("--size", type=int, default=200)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--rounds", type=int, default=4, help="Mitsuba renders profiled (rtlang renders rounds × spp)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sampler", default="multijitter", help="Mitsuba's sampler")
    ap.add_argument("--keep", type=pathlib.Path,
                    help="a folder to keep the profiles in (SCENE-rtlang.data, SCENE-mitsuba.data), for perf report")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--fifos", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child:
        return mitsuba_child(args)

    sys.path.insert(0, str(HERE))
    import suite as S  # noqa: E402
    import common  # noqa: E402
    rtlang = args.rtlang or common.rtlang_binary()
    print(f"{args.size} px, {args.spp} spp, {args.rounds} rounds, {args.threads} threads; µs of CPU per sample")
    print("| scene | renderer | closest-hit tracing | shadow tracing | the rest | all |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        keep = args.keep or pathlib.Path(tmp)
        keep.mkdir(parents=True, exist_ok=True)
        for mod in S.scene_modules(pathlib.Path(args.suite), args.scenes):
            size = S.frame(mod, args.size)
            pixels = size[0] * size[1]
            spp = args.spp * args.rounds
            cmd = S.rtlang_command(rtlang, mod, S.scene_defines(mod), size, spp, 1, args.threads,
                                   pathlib.Path(tmp) / "r.exr")
            data, out = profile(cmd, keep, f"{mod.__name__}-rtlang")
            rate = float(S.RATE.search(out).group(1)) * 1e6
            shares, _ = split(perf_rows(data), lambda dso, sym: rtlang_parts(sym))
            # The render's CPU time: its samples over its rate, both threads busy.
            per = args.threads / rate * 1e6
            print(f"| {mod.__name__} | rtlang | {shares['closest'] * per:.3f} | {shares['shadow'] * per:.3f}"
                  f" | {shares['rest'] * per:.3f} | {per:.3f} |", flush=True)
            fifos = [pathlib.Path(tmp) / n for n in ("ctl", "ack")]
            for f in fifos:
                if not f.exists():
                    os.mkfifo(f)
            child = [sys.executable, __file__, "--child", mod.__name__, "--suite", args.suite, "--size",
                     str(args.size), "--spp", str(args.spp), "--rounds", str(args.rounds), "--threads",
                     str(args.threads), "--sampler", args.sampler, "--fifos", ",".join(map(str, fifos))]
            control = ["--control", f"fifo:{fifos[0]},{fifos[1]}", "--delay", "-1"]
            data, out = profile(child, keep, f"{mod.__name__}-mitsuba", control)
            seconds = float(re.search(r"rendered ([\d.]+) s", out).group(1))
            shares, kept = split(perf_rows(data), mitsuba_parts)
            cpu = sample_count(data) / FREQ * kept
            per = cpu / (pixels * spp) * 1e6
            print(f"| {mod.__name__} | Mitsuba | {shares['closest'] * per:.3f} | {shares['shadow'] * per:.3f}"
                  f" | {shares['rest'] * per:.3f} | {per:.3f} |", flush=True)
            print(f"|  | (Mitsuba {pixels * spp / seconds / 1e6:.2f} M samples/s, rtlang {rate / 1e6:.2f}) | | | | |")


if __name__ == "__main__":
    main()
