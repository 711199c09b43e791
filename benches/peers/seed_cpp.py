#!/usr/bin/env python3
"""rtlang against the seed, the C++ path tracer it re-creates
(github.com/everaindcy/ComputerGraphics), on the seed's own scenes at equal
size, samples per pixel and maximum depth, rtlang with `--integrator path`.

    git clone https://github.com/everaindcy/ComputerGraphics /tmp/seed-src
    python3 benches/peers/seed_cpp.py --seed-src /tmp/seed-src [--rounds 3]

It compiles the seed's sources with seed_main.cpp (this folder) into a
scratch folder (`--work`, default /tmp/rtlang-seed-peer; the seed's code
never enters this repository), then for each scene renders with both
renderers, alternating, one render at a time, `--threads` threads each
(default 2). The seed runs twice per round (`--seed-mode both`): with
OpenMP threads like its main.cc (OMP_NUM_THREADS), and as forked
single-threaded processes like its main_multi_process.cc, which its report
says it used on Linux because OpenMP did poorly there (its threads share
one global random number generator). Times are the render alone:
the seed driver's timer around its pixel loop, rtlang's printed samples/s
(its scene parse and BVH build excluded); each process's whole wall time is
printed beside them. Prints every round, then per scene the medians,
samples/s of each, the ratio rtlang/seed, rays per sample and rays/s of
each (rtlang's path integrator ends paths by Russian roulette, the seed's
only at the depth limit, so the two ratios differ), and the two images' mean colours
(each decoded from its 8-bit file, clamped to [0, 1], linear), which agree
when the two scenes are the same. On a shared machine each render first
waits (`--idle-wait`) for the others' load to pass; the cpu/wall figure of
every render shows whether it had its cores.
"""

import argparse
import os
import pathlib
import re
import resource
import shutil
import statistics
import subprocess
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
DEFAULT_RTLANG = ROOT / "target" / "release" / "rtlang"

# name: (rtlang scene file, width, height, spp, the seed's depth, -D overrides).
# Sizes keep the scene's aspect at 200 px on the longer side. `{tex}` is the
# seed's textures folder, `{assets}` the shared assets folder.
SCENES = {
    "spheres": ("spheres.rt", 200, 112, 64, 70, []),
    "cornell": ("cornell.rt", 200, 200, 32, 50, []),
    "cornell_smoke": ("cornell_smoke.rt", 200, 200, 32, 50, []),
    "next_week": ("next_week.rt", 200, 200, 32, 50, ["earth={tex}/earthmap.jpg"]),
    "revolution": ("revolution.rt", 200, 112, 32, 50, []),
    "vase": ("vase.rt", 200, 180, 32, 200, ["texture={tex}/bottle.jpg"]),
    "mesh": ("mesh.rt", 200, 112, 32, 50, ["bunny={assets}/meshes/bunny_28k.obj"]),
}

# mesh.rt scales the stored 28k bunny by 12 and stands it on the floor at
# y = 0.01 (its lowest point is y = 0.0333 as stored); the seed's scene reads
# meshs/bunny/bunny.obj as is, so it gets this transform baked in.
BUNNY_SCALE, BUNNY_LIFT = 12.0, 0.01 - 12.0 * 0.0333


def build(seed_src, work):
    work.mkdir(parents=True, exist_ok=True)
    exe = work / "seed_bench"
    cmd = ["g++", "-O2", "-fopenmp", "-std=c++17", "-I", str(seed_src / "src"),
           str(HERE / "seed_main.cpp"), "-o", str(exe)]
    print("build:", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:  # its warnings (the seed's main lacks a return) only on failure
        raise SystemExit(p.stderr)
    # The folder the seed runs in: its textures, and the bunny stand-in.
    run = work / "run"
    (run / "meshs" / "bunny").mkdir(parents=True, exist_ok=True)
    link = run / "textures"
    if link.is_symlink() or link.exists():
        link.unlink()
    link.symlink_to(seed_src / "textures")
    return exe, run


def write_bunny(assets, run):
    out = []
    for line in (assets / "meshes" / "bunny_28k.obj").read_text().splitlines():
        if line.startswith("v "):
            x, y, z = (float(t) for t in line.split()[1:4])
            line = f"v {x * BUNNY_SCALE:.9g} {y * BUNNY_SCALE + BUNNY_LIFT:.9g} {z * BUNNY_SCALE:.9g}"
        out.append(line)
    (run / "meshs" / "bunny" / "bunny.obj").write_text("\n".join(out) + "\n")


def read_ppm(path):
    """Width, height and the values of a plain (P3) PPM, as both write."""
    tok = path.read_bytes().split()
    assert tok[0] == b"P3", path
    w, h = int(tok[1]), int(tok[2])
    return w, h, [int(t) for t in tok[4:4 + 3 * w * h]]


def mean_rgb(values, decode):
    table = [decode(v) for v in range(256)]
    n = len(values) // 3
    return [sum(table[v] for v in values[c::3]) / n for c in range(3)]


def seed_decode(v):
    # The seed writes int(256 · sqrt(x)) clamped to 255: the middle of the bin.
    return min(((v + 0.5) / 256.0) ** 2, 1.0)


def srgb_decode(v):
    c = v / 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def busy_cores(span=1.0):
    """Cores busy over `span` seconds (from /proc/stat), while we wait."""
    def sample():
        f = [int(x) for x in open("/proc/stat").readline().split()[1:]]
        return sum(f), f[3] + f[4]  # total, idle + iowait
    t0, i0 = sample()
    time.sleep(span)
    t1, i1 = sample()
    return (os.cpu_count() or 1) * (1 - (i1 - i0) / max(t1 - t0, 1))


def wait_idle(limit):
    """Wait up to `limit` seconds for the others' load to fall below a
    quarter core, so that a render does not share the cores; False if it
    did not."""
    end = time.monotonic() + limit
    while busy_cores() > 0.25:
        if time.monotonic() > end:
            return False
    return True


def timed(cmd, **kw):
    """Run cmd; its result, wall seconds and CPU seconds (user + system of
    it and its children): CPU / wall near the thread count means the
    render had the cores to itself, well below it that others took them."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, check=True, **kw)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return p, wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def run_seed(exe, run, name, w, h, spp, depth, threads, procs, out):
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    cmd = [str(exe), name, str(w), str(h), str(spp), str(depth), "-o", str(out)]
    if procs:
        cmd += ["--procs", str(procs)]
    p, wall, cpu = timed(cmd, cwd=run, env=env)
    secs = float(re.search(r"render_seconds ([\d.]+)", p.stdout).group(1))
    rays = int(re.search(r"rays (\d+)", p.stdout).group(1))
    return secs, wall, cpu, rays / (w * h * spp)


def run_rtlang(rtlang, scene, w, h, spp, depth, threads, defines, rnd, out):
    cmd = [str(rtlang), "render", str(ROOT / "scenes" / scene), "--width", str(w),
           "--height", str(h), "--spp", str(spp), "--max-depth", str(depth),
           "--threads", str(threads), "--integrator", "path", "--quiet",
           "--seed", str(rnd + 1), "-o", str(out)]
    for d in defines:
        cmd += ["-D", d]
    p, wall, cpu = timed(cmd)
    # "rendered OUT in X s at S of S spp: R M samples/s, ..." — X has two
    # decimals, so the time is taken from the rate, which has four figures.
    m = re.search(r"rendered .* in ([\d.]+) s at .*?([\d.]+) M samples/s, ([\d.]+) M rays/s", p.stderr)
    rate = float(m.group(2)) * 1e6
    return w * h * spp / rate, wall, cpu, float(m.group(3)) / float(m.group(2))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed-src", type=pathlib.Path, required=True,
                    help="a checkout of everaindcy/ComputerGraphics")
    ap.add_argument("--work", type=pathlib.Path, default=pathlib.Path("/tmp/rtlang-seed-peer"),
                    help="scratch folder for the seed's build and both renderers' images")
    ap.add_argument("--assets", type=pathlib.Path, default=ROOT.parent / "shared" / "assets",
                    help="the shared assets (meshes/bunny_28k.obj)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2,
                    help="rtlang's threads, the seed's OpenMP threads and forked processes")
    ap.add_argument("--seed-mode", choices=["omp", "fork", "both"], default="both",
                    help="the seed's parallelism: OpenMP threads (its main.cc), forked "
                         "processes (its main_multi_process.cc, what it used on Linux), or both")
    ap.add_argument("--rtlang", type=pathlib.Path, default=DEFAULT_RTLANG,
                    help="the rtlang binary (default: target/release/rtlang)")
    ap.add_argument("--idle-wait", type=float, default=120,
                    help="before each render wait up to this many seconds for the machine to be"
                         " idle (0: do not wait); renders that started on a busy machine are marked *")
    ap.add_argument("--spp", type=int, help="samples per pixel for every scene (default: per scene)")
    ap.add_argument("--only", nargs="+", choices=sorted(SCENES), help="these scenes only")
    args = ap.parse_args()
    rtlang = args.rtlang.resolve()
    if not rtlang.exists():
        raise SystemExit(f"build rtlang first: {rtlang} is missing (cargo build --release)")

    seed_src, assets = args.seed_src.resolve(), args.assets.resolve()
    args.work = args.work.resolve()
    exe, run = build(seed_src, args.work)
    names = args.only or list(SCENES)
    # Each scene's (file, width, height, spp, depth, defines), --spp applied.
    settings = {n: (f, w, h, args.spp or spp, d, defs) for n, (f, w, h, spp, d, defs) in SCENES.items()}
    if "mesh" in names:
        write_bunny(assets, run)
    fill = {"tex": seed_src / "textures", "assets": assets}
    seeds = {"omp": ["seed-omp"], "fork": ["seed-fork"], "both": ["seed-omp", "seed-fork"]}[args.seed_mode]
    who_all = seeds + ["rtlang"]

    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    flags = next((l for l in open("/proc/cpuinfo") if l.startswith("flags")), "").split()
    simd = ", ".join(f for f in ("avx2", "avx512f") if f in flags) or "no AVX2"
    print(f"rtlang: {rtlang} (built {time.ctime(rtlang.stat().st_mtime)})")
    print(f"CPU: {cpu} ({simd}), {os.cpu_count()} cores; {args.threads} threads (or processes) each;"
          f" rtlang --integrator path; seed-omp = OpenMP threads, seed-fork = forked processes")

    binary = rtlang.stat().st_mtime
    cpus, marks = {}, {}
    times = {n: {w: [] for w in who_all} for n in names}
    per_sample = {n: {w: [] for w in who_all} for n in names}
    walls = {n: {w: [] for w in who_all} for n in names}
    for rnd in range(args.rounds):
        for name in names:
            scene, w, h, spp, depth, defs = settings[name]
            defs = [d.format(**fill) for d in defs]
            k = rnd % len(who_all)  # a different renderer goes first each round
            for who in who_all[k:] + who_all[:k]:
                out = args.work / f"{who}-{name}.ppm"
                idle = wait_idle(args.idle_wait) if args.idle_wait > 0 else True
                marks[who] = "" if idle else "*"
                if who == "rtlang":
                    sec, wall, cpu, rps = run_rtlang(rtlang, scene, w, h, spp, depth, args.threads, defs, rnd, out)
                else:
                    procs = args.threads if who == "seed-fork" else 0
                    sec, wall, cpu, rps = run_seed(exe, run, name, w, h, spp, depth, args.threads, procs, out)
                times[name][who].append(sec)
                walls[name][who].append(wall)
                cpus[who] = cpu / wall
                per_sample[name][who].append(rps)
            print(f"round {rnd + 1} {name:14s} " + "   ".join(
                f"{who} {times[name][who][-1]:7.3f} s{marks[who]} (process {walls[name][who][-1]:6.3f} s,"
                f" cpu/wall {cpus[who]:.2f})" for who in who_all), flush=True)

    print(f"\nRender time alone (seed: its render loop, timed by seed_main.cpp; rtlang: from its"
          f" printed samples/s, scene parse and BVH build excluded), median of {args.rounds} rounds;"
          f" M samples/s = width·height·spp / time; ratio = rtlang's samples/s over the seed's.")
    head = f"{'scene':14s} {'size':>8s} {'spp':>4s} {'depth':>5s}"
    head += "".join(f" {who + ' s':>13s}" for who in who_all)
    head += "".join(f" {who + ' Ms/s':>16s}" for who in who_all)
    head += "".join(f" {'rtlang/' + who:>17s}" for who in seeds)
    print(head)
    for name in names:
        _, w, h, spp, depth, _ = settings[name]
        t = {who: statistics.median(v) for who, v in times[name].items()}
        rate = {who: w * h * spp / t[who] / 1e6 for who in who_all}
        line = f"{name:14s} {f'{w}x{h}':>8s} {spp:4d} {depth:5d}"
        line += "".join(f" {t[who]:13.3f}" for who in who_all)
        line += "".join(f" {rate[who]:16.3f}" for who in who_all)
        line += "".join(f" {rate['rtlang'] / rate[who]:16.2f}x" for who in seeds)
        print(line)

    print("\nRays per sample (the seed: calls of its world's hit(), counted by seed_main.cpp;"
          " rtlang: its printed rays/s over samples/s; rtlang's path integrator ends paths by"
          " Russian roulette, the seed only at the depth limit) and M rays/s at the median times:")
    head = f"{'scene':14s}" + "".join(f" {who + ' rays/smp':>18s}" for who in who_all)
    head += "".join(f" {who + ' Mrays/s':>17s}" for who in who_all)
    head += "".join(f" {'rays/s rtl/' + who:>20s}" for who in seeds)
    print(head)
    for name in names:
        _, w, h, spp, depth, _ = settings[name]
        rps = {who: statistics.mean(v) for who, v in per_sample[name].items()}
        mrays = {who: w * h * spp * rps[who] / statistics.median(times[name][who]) / 1e6
                 for who in who_all}
        line = f"{name:14s}" + "".join(f" {rps[who]:18.2f}" for who in who_all)
        line += "".join(f" {mrays[who]:17.2f}" for who in who_all)
        line += "".join(f" {mrays['rtlang'] / mrays[who]:19.2f}x" for who in seeds)
        print(line)

    print(f"\nWhole process wall time (scene parse, BVH and texture load, render, image write),"
          f" median of {args.rounds} rounds, seconds:")
    print(f"{'scene':14s}" + "".join(f" {who:>10s}" for who in who_all))
    for name in names:
        print(f"{name:14s}" + "".join(f" {statistics.median(walls[name][who]):10.3f}" for who in who_all))

    print("\nMean colour of the last round's images (8-bit files decoded to linear, clamped to 1);"
          " the difference is rtlang's against the seed's:")
    seed_who = seeds[-1]
    print(f"{'scene':14s} {seed_who + ' rgb':>24s} {'rtlang rgb':>24s} {'largest rel. diff':>17s}")
    for name in names:
        sw, sh, sv = read_ppm(args.work / f"{seed_who}-{name}.ppm")
        rw, rh, rv = read_ppm(args.work / f"rtlang-{name}.ppm")
        assert (sw, sh) == (rw, rh), (name, sw, sh, rw, rh)
        sm, rm = mean_rgb(sv, seed_decode), mean_rgb(rv, srgb_decode)
        diff = max(abs(a - b) / max(b, 1e-6) for a, b in zip(rm, sm))
        fmt = lambda c: " ".join(f"{x:.4f}" for x in c)
        print(f"{name:14s} {fmt(sm):>24s} {fmt(rm):>24s} {100 * diff:16.1f}%")
    print(f"\nImages: {args.work}/{{seed-omp,seed-fork,rtlang}}-SCENE.ppm")
    if rtlang.stat().st_mtime != binary:
        print(f"WARNING: {rtlang} was rebuilt during the run; the rounds measured different builds")


if __name__ == "__main__":
    if shutil.which("g++") is None:
        raise SystemExit("g++ is needed to build the seed")
    main()
