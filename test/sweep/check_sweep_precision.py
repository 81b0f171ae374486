#!/usr/bin/env python3
"""Seeds where they matter: `sweep --precision` on a tiny arena stops when every group's 95 %
interval of final P, the bootstrap over seeds of its tables (checked against bootstrap.csv with this file's own
arithmetic), is within the precision of its mean, or at the cap; it resumes after SIGINT in the middle of a
round without redoing a run, and redoes nothing once done; `--group-runs` gives a group its own seeds;
`paper --decide`'s loop against the real paper_report.py --json on the sweep's records. The rule on hand-built
values and the choice of seeds on a stub are test/python/test_sweep_rounds.py."""
import argparse
import csv
import glob
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import percentile, sigint_default  # noqa: E402

from swarm_forage.study import steps as paper_steps  # noqa: E402
from swarm_forage.sweep import rounds as rr  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SWEEP = ['rosrun', 'swarm_forage', 'sweep']
PRECISION, START, CAP = 0.35, 2, 6
SPEC = """name: precision
arena: %s
controllers: [crw, dpo]
sizes: [2, 8]
runs: %d
ticks: 3000
sample_interval: 1000
""" % (os.path.join(HERE, '..', 'fixtures', 'arena_10x5.yaml'), CAP)
ARGS = ['--precision', str(PRECISION), '--start-runs', str(START), '-j', '2']


def final_p(path):
    with rosbag.Bag(path) as bag:
        perf = [m for _, m, _ in bag.read_messages(topics=['/world/performance'])]
    return perf[-1].cumulative


def bootstrap_p(out):
    """identity -> (draw 0, 2.5 % and 97.5 % percentiles of draws 1 ... B, clipped at 0) of P in
    OUT/tables/bootstrap.csv."""
    columns = {}
    with open(os.path.join(out, 'tables', 'bootstrap.csv')) as f:
        for r in csv.DictReader(f):
            columns.setdefault(r['identity'], {})[int(r['draw'])] = float(r['P'])
    return {i: (c[0], max(0.0, percentile([v for d, v in c.items() if d], 0.025)),
                max(0.0, percentile([v for d, v in c.items() if d], 0.975))) for i, c in columns.items()}


def records(out):
    """group -> {seed: path} of the finished records."""
    groups = {}
    for path in glob.glob(os.path.join(out, 'runs', '*.bag')):
        m = re.match(r'(.*)_seed(\d+)_[0-9a-f]{8}\.bag$', os.path.basename(path))
        if m:  # the record's name less its arena is the group's: crw_10x5_n8_null_seed1_ID -> crw_n8_null
            groups.setdefault(re.sub(r'_[^_]+(_n\d+_)', r'\1', m.group(1), count=1), {})[int(m.group(2))] = path
    return groups


class SweepPrecision(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_precision_'))
        cls.spec = write(cls.tmp, 'precision.yaml', SPEC)
        cls.out = os.path.join(cls.tmp, 'out')

    def sweep(self, *args):
        return subprocess.run(SWEEP + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=600)

    def test_1_rounds_stop_at_the_precision_and_resume_after_sigint(self):
        log = os.path.join(self.tmp, 'first.log')
        with open(log, 'w') as f:
            proc = subprocess.Popen(SWEEP + [self.spec, '--out', self.out] + ARGS, stdout=f, stderr=subprocess.STDOUT,
                                    text=True, start_new_session=True, preexec_fn=sigint_default)
        runs, deadline = os.path.join(self.out, 'runs'), time.time() + 400
        while time.time() < deadline and proc.poll() is None:
            # A run of round 2 (a seed above the start) in flight: SIGINT now interrupts a round. At once: on an
            # idle machine a run of this tiny sweep can end within 0.3 s (seen: 16 runs in 7 s on 2 slots).
            if any(int(re.search(r'_seed(\d+)_', p).group(1)) > START
                   for p in glob.glob(os.path.join(runs, '*.bag.*.active'))):
                break
            time.sleep(0.005)
        else:
            proc.kill()
            proc.wait()
            with open(log) as f:
                self.fail('no run of round 2 in flight: %s' % f.read()[-3000:])
        os.killpg(proc.pid, signal.SIGINT)
        proc.wait(timeout=120)
        with open(log) as f:
            first = f.read()
        self.assertNotEqual(proc.returncode, 0, first)
        self.assertIn('round 1: 4 groups, %d seeds each (cap %d, precision %g)' % (START, CAP, PRECISION), first)
        self.assertIn('round 2:', first)
        self.assertIn('the same command resumes', first)
        finished = {p: (os.stat(p).st_ino, os.stat(p).st_mtime_ns) for p in glob.glob(os.path.join(runs, '*.bag'))
                    if not p.endswith('_incomplete.bag')}
        with open(os.path.join(self.out, rr.STATE)) as f:
            state = f.read()
        self.assertIn('# round 2', state)

        again = self.sweep(self.spec, '--out', self.out, *ARGS)
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertIn('round 2 (resumed: the seeds the last call chose)', again.stdout)
        self.assertNotIn('round 1:', again.stdout)
        for p, ident in finished.items():
            self.assertEqual((os.stat(p).st_ino, os.stat(p).st_mtime_ns), ident, '%s was redone' % p)
        self.assertRegex(again.stdout, r'\d+ runs \(%d done, \d+ to do\)' % len(finished))

        # Where the rule stops, from the records' own final P and the tables' bootstrap.
        groups = records(self.out)
        self.assertEqual(len(groups), 4, groups)
        with open(os.path.join(self.out, 'tables', 'series.csv')) as f:
            tables = {}
            for r in csv.DictReader(f):
                tables[(r['controller'], int(r['swarm_size']))] = int(r['runs'])
        listing = {r['group']: r for r in rr.read_groups(self.out)}
        intervals = bootstrap_p(self.out)
        statuses = set()
        for group, seeds in groups.items():
            n = len(seeds)
            self.assertEqual(sorted(seeds), list(range(1, n + 1)), '%s: seeds 1 ... n, no gap' % group)
            finals = [final_p(seeds[s]) for s in sorted(seeds)]
            mean = sum(finals) / n
            row = listing[group]
            self.assertEqual(int(row['runs']), n)
            self.assertEqual(tables[(row['controller'], int(row['N']))], n)
            estimate, lo, hi = intervals[row['identity']]
            self.assertAlmostEqual(estimate, mean, places=6)
            self.assertAlmostEqual(float(row['P_mean']), mean, places=6)
            self.assertAlmostEqual(float(row['P_low']), lo, places=6)
            self.assertAlmostEqual(float(row['P_high']), hi, places=6)
            if max(mean - lo, hi - mean) <= PRECISION * mean:
                statuses.add('precise')
                self.assertRegex(again.stdout, r'%s: %d seeds, final P .*: precise' % (re.escape(group), n))
            else:
                statuses.add('capped')
                self.assertEqual(n, CAP, group)
                self.assertRegex(again.stdout, r'%s: %d seeds, final P .*: capped' % (re.escape(group), n))
            if n > START:  # a round judged it not precise and chose its next count
                self.assertRegex(first + again.stdout, r'%s: \d+ seeds, final P .*: not within %g %%: \d+ seeds next'
                                 % (re.escape(group), 100 * PRECISION))
        self.assertIn('every group precise or capped after round', again.stdout)
        print('groups: %s' % ', '.join('%s %d' % (g, len(s)) for g, s in sorted(groups.items())))

        # Once more: nothing to do, nothing redone.
        bags = {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(runs, '*.bag'))}
        third = self.sweep(self.spec, '--out', self.out, *ARGS)
        self.assertEqual(third.returncode, 0, third.stdout)
        self.assertIn('(resumed: the seeds the last call chose)', third.stdout)
        self.assertRegex(third.stdout, r'\(\d+ done, 0 to do\)')
        self.assertEqual({p: os.stat(p).st_mtime_ns for p in bags}, bags)

    def test_2_group_runs_give_a_group_its_seeds(self):
        self.assertTrue(os.path.isdir(self.out), 'test 1 makes the sweep')
        rows = rr.read_groups(self.out)
        one = rows[0]['group']
        path = write(self.tmp, 'seeds.tsv', '# a comment\n%s\t1\n' % one)
        proc = self.sweep(self.spec, '--out', self.out, '--runs', '2', '--group-runs', path)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('0 to do', proc.stdout)  # seeds 1 and 2 are recorded
        listing = {r['group']: int(r['runs']) for r in rr.read_groups(self.out)}
        self.assertEqual(listing, {r['group']: 1 if r['group'] == one else 2 for r in rows})
        for text, message in (('nogroup\t3\n', 'group nogroup is not a group of precision (4 groups, e.g.'),
                              ('%s\tmany\n' % one, 'want GROUP<TAB>RUNS'), ('%s\t2\n%s\t3\n' % (one, one), 'listed twice')):
            proc = self.sweep(self.spec, '--out', self.out, '--group-runs', write(self.tmp, 'bad.tsv', text))
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)
        proc = self.sweep(self.spec, '--out', self.out, '--precision', '0.05', '--group-runs', path)
        self.assertEqual(proc.returncode, 2, proc.stdout)

    def test_3_paper_decide_against_the_real_report(self):
        """paper's decide loop (swarm_forage.study.steps, its sweeps in this process) on the tiny sweep as a
        one-sweep study (claim (c): CRW against DPO at the largest N, 8), from 2 seeds per group up to a cap of 6:
        it redoes none of test 1's records and runs only seeds of the groups it raises that test 1 did not record;
        it ends with (c) decided or its groups at the cap."""
        self.assertTrue(os.path.isdir(self.out), 'test 1 makes the sweep')
        bags = {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(self.out, 'runs', '*.bag'))}
        plan = [('out', self.spec[:-len('.yaml')], ['--runs', '2'])]
        a = argparse.Namespace(arm_96=True, cap=CAP, report_only=False)
        paper_steps.run_sweep(self.tmp, 'out', plan[0][1], plan[0][2], ['-j', '2'])
        paper_steps.decide(a, self.tmp, plan, ['-j', '2'], os.path.join(self.tmp, 'figures'))
        with open(os.path.join(self.tmp, 'verdicts.json')) as f:
            claims = {c['claim']: c for c in json.load(f)}
        c = claims['c']
        self.assertEqual(sorted(g[2] for g in c['groups']), ['crw', 'dpo'])
        self.assertEqual({g[3] for g in c['groups']}, {8})
        runs = {r['group']: int(r['runs']) for r in rr.read_groups(self.out)}
        seeds = rr.read_group_runs(os.path.join(self.tmp, 'seeds', 'out.tsv'))
        self.assertEqual(sorted(seeds), ['crw_n8_null', 'dpo_n8_null'])
        for group, n in runs.items():
            self.assertEqual(n, seeds.get(group, 2), group)  # the raised groups have their seeds, the others --runs
        self.assertGreaterEqual(min(seeds.values()), 3)  # at least MIN_SEEDS, which the report asked for
        self.assertTrue(c['verdict'] != 'undecided' or all(seeds[g] == CAP for g in seeds), c)
        after = {p: os.stat(p).st_mtime_ns for p in glob.glob(os.path.join(self.out, 'runs', '*.bag'))}
        self.assertEqual({p: after.get(p) for p in bags}, bags)  # none redone
        for group, by_seed in records(self.out).items():
            for seed, path in by_seed.items():
                if path not in bags:  # new: a seed of a raised group, within what the report asked
                    self.assertLessEqual(seed, seeds.get(group, 0), path)
        print('paper --decide: (c) %s with %s seeds, %d records new' % (c['verdict'], seeds, len(after) - len(bags)))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'sweep_precision', SweepPrecision)
