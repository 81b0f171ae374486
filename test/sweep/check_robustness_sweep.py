#!/usr/bin/env python3
"""Robustness sweeps: bad values of the experiment files' noise and population axes refused before any run
(their expansion and the file's form: test/python/test_robustness_axes.py), and a tiny SAA sweep and a tiny
PD sweep through the real `sweep`, each giving its robustness tables, its figures (plot_sweep.py) and the
report's "Beyond the paper" section (paper_report.py --robustness). The PD tables carry the queue the measure assumes beside what the records'
world/population show, counted here apart from the core."""
import csv
import glob
import os
import subprocess
import sys
import tempfile
import unittest

import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import experiment_text, sweep  # noqa: E402
from swarm_forage.robustness import figures, tables

SCRIPTS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), 'scripts')
PLAIN = experiment_text('tiny_robustness', [8], 1000, 250)
# 16 robots for 3,000 ticks: every controller delivers blocks (with none, P(t) = 0 with noise and without).
SAA_PLAIN = PLAIN.replace('sizes: [8]', 'sizes: [16]').replace('ticks: 1000', 'ticks: 3000')
SAA = SAA_PLAIN + 'noise:\n  - {all/model: gaussian, all/level: [0, 0.03]}\n'
# Rates high enough that a 1,000-tick run sees events: about 5 malfunctions (repairs take 100 ticks on
# average) and 5 deaths; the queue is stable (lambda = 1e-2 < mu = 1e-2 + 5e-3).
PD = PLAIN + ('population:\n  - {}\n  - {death: 5.0e-3, birth: 5.0e-3, malfunction: 5.0e-3, repair: 1.0e-2}\n'
              '  - {death: 5.0e-3}\n')


def out_of_swarm(path):
    """What one record's world/population shows: (ticks, robot-ticks out of the swarm, outages that ended,
    their ticks summed). An id is out from its death or malfunction (the first, if both) to its birth or
    repair, events taken in the world's order within a tick."""
    import rosbag
    since, ticks, robot_ticks, ended, ended_ticks = {}, 0, 0, 0, 0
    with rosbag.Bag(path) as bag:
        for _, m, _ in bag.read_messages(topics=['/world/population']):
            assert m.tick == ticks, 'tick %d after %d ticks' % (m.tick, ticks)
            for leaving, ids in ((True, m.deaths), (False, m.births), (True, m.malfunctions), (False, m.repairs)):
                for i in ids:
                    if leaving:
                        since.setdefault(i, m.tick)
                    elif i in since:
                        ended, ended_ticks = ended + 1, ended_ticks + m.tick - since.pop(i)
            ticks += 1
            robot_ticks += m.max_size - m.active
    return ticks, robot_ticks, ended, ended_ticks


def queue_expected(death, birth, malfunction, repair, ticks, robot_ticks, ended, ended_ticks):
    """The queue fields robustness.csv should carry, as floats (None: empty): W, measured time out, L, measured
    robots out, outages, differs."""
    lam, mu = death + malfunction, birth + repair
    w = 1 / (mu - lam) if lam < mu else None
    l = lam / (mu - lam) if lam < mu else None
    t = ended_ticks / ended if ended else None
    n = robot_ticks / ticks
    pairs = [(p, m) for p, m in ((w, t), (l, n)) if p is not None and m is not None]
    differs = any(abs(m - p) > 0.2 * p for p, m in pairs) if pairs else None
    return w, t, l, n, ended, differs


def table(out, name):
    with open(os.path.join(out, 'tables', name + '.csv')) as f:
        return list(csv.DictReader(f))


class RobustnessSweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_robustness_'))

    def sweep(self, *args):
        return sweep(*args)

    def test_2_bad_axis_values_are_refused_before_any_run(self):
        """run_experiment's start-up check, which `sweep` runs for every setting before any run (exit 2); the
        file's form (refused when read) is test/python/test_robustness_axes.py."""
        by_sweep = [
            (PLAIN + 'noise:\n  - {all/levle: 0.01}\n', 'noise[0]: unknown key all/levle'),
            (PLAIN + 'noise:\n  - {all/level: [0, -0.01]}\n', '~noise/all/level must be in [0, 1] (got -0.01)'),
            (PLAIN + 'population:\n  - {death: -1.0e-4}\n', '~population/death must be in [0, 1] (got -0.0001)'),
        ]
        for k, (text, message) in enumerate(by_sweep):
            out = os.path.join(self.tmp, 'bad%d' % k)
            proc = self.sweep(write(self.tmp, 'bad%d.yaml' % k, text), '--out', out)
            self.assertEqual(proc.returncode, 2, 'case %d: %s' % (k, proc.stdout))
            self.assertIn(message, proc.stdout, 'case %d' % k)
            self.assertFalse(glob.glob(os.path.join(out, 'runs', '*')), 'case %d ran something' % k)
        proc = self.sweep(write(self.tmp, 'plain_levels.yaml', PLAIN), '--out', os.path.join(self.tmp, 'x'),
                          '--noise-levels', '0,0.01')
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('--noise-levels: no noise setting has a list of levels', proc.stdout)

    def run_sweep(self, name, text):
        out = os.path.join(self.tmp, name)
        proc = self.sweep(write(self.tmp, name + '.yaml', text), '--out', out, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        drawn = os.path.join(self.tmp, name + '_figures')
        plot = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'plot_sweep.py'), out, '--output', drawn],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(plot.returncode, 0, plot.stdout)
        report = os.path.join(self.tmp, name + '_report.md')
        rep = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'paper_report.py'), '--ideal', out,
                              '--robustness', out, '--output', report],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(rep.returncode, 0, rep.stdout)
        with open(report) as f:
            return out, plot.stdout.split(), f.read()

    def test_3_tiny_saa_sweep_gives_tables_figures_and_verdicts(self):
        out, files, report = self.run_sweep('saa', SAA)
        rows = [r for r in table(out, 'robustness') if r['measure'] == 'saa' and float(r['noise_level']) > 0]
        self.assertEqual(sorted(r['controller'] for r in rows), ['crw', 'dpo'])
        for r in rows:
            self.assertEqual(r['valid'], '1', r)
            self.assertGreater(float(r['P_reference']), 0.0, r)
            self.assertGreater(float(r['value']), 0.0, r)  # noise changes P(t): a distance above 0
            self.assertTrue(-1.0 < float(r['normalized']) < 0.0, r)
        per_run = [r for r in table(out, 'robustness_runs') if r['measure'] == 'saa' and r['valid'] == '1']
        self.assertEqual(sorted((r['controller'], r['seed']) for r in per_run),
                         [('crw', '1'), ('crw', '2'), ('dpo', '1'), ('dpo', '2')])
        points = tables.read(out)
        self.assertEqual({(p['controller'], p['noise_level']) for p in points}, {('crw', 0.03), ('dpo', 0.03)})
        self.assertTrue(all(sorted(p['seeds']) == [1, 2] for p in points))
        self.assertTrue(any(f.endswith('robustness_saa_32x16.png') for f in files), files)
        self.assertIn('## Beyond the paper: robustness', report)
        self.assertIn('| saa, SAA, 32x16, N = 16 |', report)
        self.assertIn('Settings compared: level 0.03 (proximity, light, ground, position, heading, wheels).', report)

    def test_4_tiny_pd_sweep_gives_tables_figures_active_counts_and_verdicts(self):
        out, files, report = self.run_sweep('pd', PD)
        rows = [r for r in table(out, 'robustness') if r['measure'] == 'pd']
        both = [r for r in rows if float(r['birth']) > 0]
        self.assertEqual(sorted(r['controller'] for r in both), ['crw', 'dpo'])
        for r in both:
            self.assertEqual(r['valid'], '1', r)
            self.assertGreater(float(r['T_bar']), 0.0, r)
            self.assertTrue(-1.0 < float(r['normalized']) < 1.0, r)
        points = tables.read(out)
        fams = {(p['family'], p['multiplier']) for p in points}
        self.assertEqual(fams, {(('birth', 'death', 'malfunction', 'repair'), 1.0), (('death',), 1.0)})
        # The records carry world/population: robots leave (deaths, malfunctions) and the count shows it.
        top = [p for p in points if p['family'] == ('death',) and p['controller'] == 'crw'][0]
        active, records = figures._active_counts(out, 'crw', 8, top['rates'], 1)
        self.assertEqual(records, 2)
        self.assertEqual(active[0][1], 8.0)
        self.assertLess(active[-1][1], 8.0)  # 5 deaths expected per run: none in both runs has p = e^-10
        self.assertTrue(all(b <= a for (_, a), (_, b) in zip(active, active[1:])), 'death only: never grows')
        for name in ('robustness_pd_32x16.png', 'population_32x16.png'):
            self.assertTrue(any(f.endswith(name) for f in files), (name, files))
        self.assertIn('| pd, PD, 32x16, N = 8 |', report)
        self.assertIn('Queue check: ', report)

        # Beside the queue's prediction, the time out and the robots out measured from each record's
        # world/population: per run (robustness_runs.csv) and pooled over the group's runs (robustness.csv).
        import rosbag
        measured = {}  # (controller, death, birth, seed) -> counts
        for path in glob.glob(os.path.join(out, 'runs', '*.bag')):
            with rosbag.Bag(path) as bag:
                info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
            words = dict(w.split('=', 1) for w in info.world_constants.split() if w.startswith('population/'))
            if words:
                measured[(info.controller, float(words['population/death']), float(words['population/birth']),
                          info.seed)] = out_of_swarm(path)
        self.assertEqual(len(measured), 8)  # 2 controllers x 2 settings x 2 seeds

        def check(row, counts):
            rates = [float(row[r]) for r in ('death', 'birth', 'malfunction', 'repair')]
            want = queue_expected(*rates, *counts)
            got = [float(row[k]) if row[k] != '' else None for k in ('time_out_queue', 'time_out_measured',
                                                                     'out_queue', 'out_measured', 'outages')]
            got.append({'1': True, '0': False, '': None}[row['queue_differs']])
            for k, (g, w) in enumerate(zip(got, want)):
                if isinstance(w, float):
                    self.assertAlmostEqual(g, w, places=9, msg='%d: %s' % (k, row))
                else:
                    self.assertEqual(g, w, '%d: %s' % (k, row))
        per_run = [r for r in table(out, 'robustness_runs') if r['measure'] == 'pd']
        self.assertEqual(len(per_run), 8)
        for r in per_run:
            check(r, measured[(r['controller'], float(r['death']), float(r['birth']), int(r['seed']))])
        for r in rows:
            counts = [v for (c, d, b, _), v in measured.items()
                      if c == r['controller'] and d == float(r['death']) and b == float(r['birth'])]
            self.assertEqual(len(counts), 2)
            check(r, [sum(c[k] for c in counts) for k in range(4)])
            if float(r['birth']) == 0:  # death only: no steady state, no prediction, nothing to flag
                self.assertEqual((r['time_out_queue'], r['out_queue'], r['queue_differs']), ('', '', ''), r)
                self.assertGreater(float(r['out_measured']), 0.0, r)
            else:  # lambda = 0.01, mu = 0.015: W = 200 ticks, L = 2 robots
                self.assertAlmostEqual(float(r['time_out_queue']), 200.0, places=9)
                self.assertAlmostEqual(float(r['out_queue']), 2.0, places=9)
                self.assertGreater(int(r['outages']), 0, r)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'robustness_sweep', RobustnessSweep)
