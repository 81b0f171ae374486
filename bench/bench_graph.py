#!/usr/bin/env python3
"""Whole-graph throughput: robot-ticks per second of a run through the four ROS nodes in lockstep.

    bench_graph.py [--ticks K] [--case N:ARENA ...] [--controller crw|dpo|gp_dpo ...] [--nodelet]

Starts `roslaunch swarm_forage foraging.launch` for each case (with --nodelet: nodelet:=true, the four
nodes as nodelets in one process) and reads the world's own wall-clock figure from its end-of-run line,
so start-up is not counted.
"""
import argparse
import re
import subprocess
import sys

from swarm_forage.study.claims import PAPER

LINE = re.compile(r'run 0 finished: (\d+) ticks, (\d+) blocks delivered; ([\d.]+) s wall, ([\d.e+]+) robot-ticks/s')


def run_case(controller, n, arena, ticks, nodelet=False):
    """(ticks, delivered, wall seconds, robot-ticks/s) of one run of foraging.launch (nodelet: in one process)."""
    cmd = ['roslaunch', 'swarm_forage', 'foraging.launch', 'controller:=' + controller, 'n_robots:=%d' % n,
           'arena:=%s' % arena, 'ticks:=%d' % ticks, 'sample_interval:=%d' % max(1, ticks // 4),
           'nodelet:=%s' % str(nodelet).lower()]
    out = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=3600).stdout
    m = LINE.search(out)
    if not m:
        sys.exit('no end-of-run line from world_node for N=%d %s; output:\n%s' % (n, arena, out[-3000:]))
    return int(m.group(1)), int(m.group(2)), float(m.group(3)), float(m.group(4))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  bench_graph.py --ticks 500 --case 1024:32x16 --controller crw')
    ap.add_argument('--ticks', type=int, default=1000, help='ticks per case (default: %(default)s)')
    ap.add_argument('--case', action='append', help='N:ARENA, e.g. 1024:32x16 (repeatable; default: 1024:32x16 and 16384:96x48)')
    ap.add_argument('--controller', action='append', choices=list(PAPER),
                    help='controller kind (repeatable; default: all three)')
    ap.add_argument('--nodelet', action='store_true', help='the nodes as nodelets in one process (nodelet:=true)')
    args = ap.parse_args()
    if args.ticks < 1:
        ap.error('--ticks must be >= 1 (got %d)' % args.ticks)
    cases = args.case or ['1024:32x16', '16384:96x48']
    for case in cases:
        if not re.fullmatch(r'[1-9]\d*:\S+', case):
            ap.error('--case must be N:ARENA with N >= 1, e.g. 1024:32x16 (got %s)' % case)
    for controller in args.controller or PAPER:
        for case in cases:
            n, arena = case.split(':')
            ticks, delivered, wall, rate = run_case(controller, int(n), arena, args.ticks, args.nodelet)
            print('%s %s N=%s arena=%s: %.3g robot-ticks/s (%d ticks in %.2f s, lockstep, %s), delivered %d'
                  % ('nodelet' if args.nodelet else 'graph', controller, n, arena, rate, ticks, wall,
                     'one process' if args.nodelet else '4 processes', delivered), flush=True)


if __name__ == '__main__':
    main()
