#!/usr/bin/env python3
"""hard_disks (3-D spheres, cells) against Smallenburg's EDMD (github.com/FSmallenburg/EDMD, Single/),
side by side on this machine, runs alternating; prints pair collisions per CPU second and the ratio.

The reference is built from a checkout given by --edmd (nothing of it is kept in stsim): Single/ is
copied to a scratch folder, its parameters set (FCC start, packing fraction, thermostat off) and its
main loop timed after the warm-up by a small patch of main(), then compiled with its own Makefile's
flags (-Ofast -funroll-loops -march=native).

Counting: Smallenburg's box is periodic and counts pair collisions only; stsim's is walled, so its
figure here is its ball-ball collisions (hard_disks --json "ball_ball") over the same CPU time, the
wall hits left out. Both warm up first and time only what follows, over the same number of pair
collisions.

usage: vs_smallenburg.py --edmd DIR [--hard-disks build/bench/hard_disks/hard_disks] [--n 4000 32000]
                         [--phi 0.3] [--rounds 2] [--before OLD_HARD_DISKS] [--stsim-args "--shell 0"]

--before runs a second hard_disks (an older build) in the same alternation and prints its ratio
too (a hot-path change measured before/after and against the reference in one run); --stsim-args
are passed to both hard_disks runs.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

PATCH_MAIN = r"""#include <time.h>
static double cpunow(void) { struct timespec ts; clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts); return ts.tv_sec + 1e-9 * ts.tv_nsec; }
int main(int argc, char** argv)
{
    N = atoi(argv[1]);
    unsigned int warm = (unsigned int)atol(argv[2]), measure = (unsigned int)atol(argv[3]);
    maxtime = 1e9; writeinterval = 1e9;
    init();
    while (colcounter < warm) step();
    unsigned int c0 = colcounter; double t0 = cpunow();
    while (colcounter < warm + measure) step();
    double t1 = cpunow();
    printf("REFERENCE %u %.6f\n", colcounter - c0, t1 - t0);
    return 0;
}
"""


def build_reference(edmd, phi, scratch):
    src = os.path.join(edmd, "Single")
    dst = os.path.join(scratch, "Single")
    shutil.copytree(src, dst)
    path = os.path.join(dst, "mdSingle.c")
    text = open(path).read()
    text = re.sub(r"int initialconfig = \d+;", "int initialconfig = 1;", text)
    text = re.sub(r"double packfrac = [0-9.]+;", "double packfrac = %r;" % phi, text)
    text = re.sub(r"const int usethermostat = \d+;", "const int usethermostat = 0;", text)
    # main() up to its closing brace at the start of a line
    text, n = re.subn(r"int main\(\)\s*\{.*?\n\}\n", lambda _: PATCH_MAIN, text, count=1, flags=re.S)
    if n != 1:
        sys.exit("vs_smallenburg: main() not found in mdSingle.c (a newer EDMD?)")
    open(path, "w").write(text)
    subprocess.run(["make", "-s", "-C", dst], check=True, stdout=subprocess.DEVNULL)
    return os.path.join(dst, "md")


def fcc_n(n):
    # Smallenburg's FCC start needs 4 k^3 particles
    k = max(1, round((n / 4) ** (1 / 3)))
    return 4 * k ** 3


def run_reference(md, n, warm, measure, cwd):
    out = subprocess.run([md, str(n), str(warm), str(measure)], cwd=cwd, check=True, capture_output=True, text=True).stdout
    m = re.search(r"REFERENCE (\d+) ([0-9.]+)", out)
    return int(m.group(1)) / float(m.group(2))


def run_stsim(exe, n, phi, warm, measure, extra=()):
    # hard_disks counts ball-ball + ball-wall; ask for enough that the ball-ball ones reach `measure`
    out = subprocess.run([exe, "--dim", "3", "--n", str(n), "--phi", str(phi), "--space", "cells", "--collisions",
                          str(int(measure * 1.15)), "--warmup", str(warm), "--json", *extra], check=True,
                         capture_output=True, text=True).stdout
    j = json.loads(out.strip().splitlines()[-1])
    return j["ball_ball"] / j["cpu_seconds"], j["collisions"] / j["cpu_seconds"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--edmd", required=True)
    ap.add_argument("--hard-disks", default="build/bench/hard_disks/hard_disks")
    ap.add_argument("--n", type=int, nargs="+", default=[4000, 32000, 256000])
    ap.add_argument("--phi", type=float, default=0.3)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--before", help="an older hard_disks, run alternating with the others")
    ap.add_argument("--stsim-args", default="", help="extra hard_disks arguments (both builds)")
    a = ap.parse_args()
    extra = a.stsim_args.split()
    with tempfile.TemporaryDirectory() as scratch:
        md = build_reference(a.edmd, a.phi, scratch)
        print("3-D spheres, phi %.3g, pair collisions per CPU second (M/s); runs alternate, %d rounds" % (a.phi, a.rounds))
        print("%8s %22s %22s %16s %22s" % ("N", "Smallenburg Single", "stsim cells (pairs)", "ratio", "stsim incl. walls")
              + ("%22s %16s" % ("before (pairs)", "before ratio") if a.before else ""))
        for n in a.n:
            n = fcc_n(n)
            measure = min(max(2_000_000, 10 * n), 4_000_000)
            warm = max(1_000_000, 5 * n)
            ref, ours, walls, old = [], [], [], []
            for _ in range(a.rounds):
                ref.append(run_reference(md, n, warm, measure, os.path.dirname(md)) / 1e6)
                pairs, all_ = run_stsim(a.hard_disks, n, a.phi, warm, measure, extra)
                ours.append(pairs / 1e6)
                walls.append(all_ / 1e6)
                if a.before:
                    old.append(run_stsim(a.before, n, a.phi, warm, measure, extra)[0] / 1e6)
            rng = lambda v: "%.3f-%.3f" % (min(v), max(v))
            ratios = [o / r for o, r in zip(ours, ref)]
            line = "%8d %22s %22s %16s %22s" % (n, rng(ref), rng(ours), rng(ratios) + "x", rng(walls))
            if a.before:
                line += "%22s %16s" % (rng(old), rng([o / r for o, r in zip(old, ref)]) + "x")
            print(line)
            sys.stdout.flush()


if __name__ == "__main__":
    main()
