#!/usr/bin/env python3
"""Robustness sweeps: the experiment files' noise and population axes (expansion, record keys, refusals
before any run), and a tiny SAA sweep and a tiny PD sweep through the real `sweep`, each giving its
robustness tables, its figures (plot_sweep.py) and the report's "Beyond the paper" section
(paper_report.py --robustness). The PD tables carry the queue the measure assumes beside what the records'
world/population show, counted here apart from the core."""
import csv
import glob
import os
import subprocess
import sys
import tempfile
import unittest

import rostest
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import experiment_text, sweep  # noqa: E402
from swarm_forage import experiment, robustness_figures, robustness_report, robustness_tables

SCRIPTS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'scripts')
PLAIN = experiment_text('tiny_robustness', [8], 1000, 250)
# 16 robots for 3,000 ticks: every controller delivers blocks (with none, P(t) = 0 with noise and without).
SAA_PLAIN = PLAIN.replace('sizes: [8]', 'sizes: [16]').replace('ticks: 1000', 'ticks: 3000')
SAA = SAA_PLAIN + 'noise:\n  - {all/model: gaussian, all/level: [0, 0.03]}\n'
# Rates high enough that a 1,000-tick run sees events: about 5 malfunctions (repairs take 100 ticks on
# average) and 5 deaths; the queue is stable (lambda = 1e-2 < mu = 1e-2 + 5e-3).
PD = PLAIN + ('population:\n  - {}\n  - {death: 5.0e-3, birth: 5.0e-3, malfunction: 5.0e-3, repair: 1.0e-2}\n'
              '  - {death: 5.0e-3}\n')


COLUMNS = ('controller,arena,waveform,beta,environment,N,runs,measure,noise,noise_level,death,birth,malfunction,'
           'repair,max_size,T,T_bar,time_out_queue,time_out_measured,out_queue,out_measured,outages,queue_differs,'
           'P,P_reference,value,normalized,valid,status,reference,reference_runs,sample_interval,identity').split(',')


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


def hand_made(folder, rows):
    """robustness.csv and robustness_runs.csv of SAA rows (controller, N, level, seed values, valid) as
    run_tables writes them: a group row with the mean, a row per seed."""
    os.makedirs(os.path.join(folder, 'tables'))
    groups, per_run = [], []
    for k, (c, n, level, values, valid) in enumerate(rows):
        base = dict(controller=c, arena='32x16', waveform='null', beta='0', environment='null', N=n, measure='saa',
                    noise='noise/all/level=%g' % level, noise_level=level, death=0, birth=0, malfunction=0, repair=0,
                    max_size=0, T=1000, T_bar='', P=90, P_reference=100, valid=int(valid),
                    status='ok' if valid else 'no reference', reference='00000000', reference_runs=len(values),
                    sample_interval=250, identity='%08x' % (k + 1))
        mean = sum(values) / len(values)
        groups.append(dict(base, runs=len(values), value=mean, normalized=-0.5))
        per_run += [dict(base, seed=s + 1, value=v, normalized=-0.5) for s, v in enumerate(values)]
    for name, data, cols in (('robustness', groups, COLUMNS),
                             ('robustness_runs', per_run, [c if c != 'runs' else 'seed' for c in COLUMNS])):
        with open(os.path.join(folder, 'tables', name + '.csv'), 'w') as f:
            w = csv.DictWriter(f, cols)
            w.writeheader()
            w.writerows(data)
    return folder


def table(out, name):
    with open(os.path.join(out, 'tables', name + '.csv')) as f:
        return list(csv.DictReader(f))


class RobustnessSweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_robustness_'))

    def sweep(self, *args):
        return sweep(*args)

    def test_0_the_verdict_follows_its_criterion(self):
        """Hand-made tables: a clear gap gives a winner, overlapping intervals none, one seed cannot tell;
        a setting without a value for every controller is left out and named."""
        label = lambda c: c.upper()  # noqa: E731
        clear = hand_made(os.path.join(self.tmp, 'clear'), [
            ('crw', 16, 0.01, [1.0, 1.2, 1.1], True), ('dpo', 16, 0.01, [5.0, 5.2, 5.1], True),
            ('crw', 16, 0.02, [2.0, 2.2, 2.1], True), ('dpo', 16, 0.02, [9.0, 9.2, 9.1], False),
            ('crw', 64, 0.01, [1.0, 9.0, 5.0], True), ('dpo', 64, 0.01, [2.0, 8.0, 6.0], True),
            ('crw', 256, 0.01, [3.0], True), ('dpo', 256, 0.01, [4.0], True)])  # noise words: all/level=L
        found = {n: (text, winner, used, left) for _, n, _, text, winner, used, left in
                 robustness_report.verdicts(robustness_tables.read(clear), 'saa', label)}
        self.assertEqual(found[16][:3], ('CRW degrades least', 'crw', ['level 0.01 (all/level)']))
        self.assertEqual(found[16][3], {'level 0.02 (all/level)': 'DPO: no reference'})
        self.assertEqual(found[64][1], None)
        self.assertIn('no clear winner: CRW and DPO', found[64][0])
        self.assertIn('cannot tell: one seed', found[256][0])
        lines, summary = robustness_report.section([clear], label)
        self.assertIn(('clear, SAA, 32x16, N = 16', 'CRW degrades least'), summary)
        self.assertIn('| 32x16 | 16 | d 1.1 ± 0.25 (3 seeds); P -10.0 % | d 5.1 ± 0.25 (3 seeds); P -10.0 % | '
                      'CRW degrades least |', lines)

    def test_1_axes_expand_into_runs_and_plain_runs_keep_their_keys(self):
        plain = experiment.expand(experiment.load(write(self.tmp, 'saa_plain.yaml', SAA_PLAIN)))
        saa = experiment.expand(experiment.load(write(self.tmp, 'saa.yaml', SAA)))
        self.assertEqual(len(saa), 2 * len(plain))
        noisy = [r for r in saa if r['noise']]
        self.assertEqual(len(noisy), len(plain))
        for r in noisy:
            self.assertIn('noise/all/level:=0.03', r['args'])
            self.assertIn('noise/all/model:=gaussian', r['args'])
            self.assertIn('_saa-all-gaussian0.03_', r['key'])
        # Level 0 is the plain run: no noise words, the key of the same run without the axis.
        self.assertEqual(sorted(r['key'] for r in saa if not r['noise']), sorted(r['key'] for r in plain))
        plain = experiment.expand(experiment.load(write(self.tmp, 'plain.yaml', PLAIN)))
        pd = experiment.expand(experiment.load(write(self.tmp, 'pd.yaml', PD)))
        self.assertEqual(len(pd), 3 * len(plain))
        death = [r for r in pd if r['population'] == 'pd-d0.005']
        self.assertEqual(len(death), len(plain))
        self.assertEqual([w for w in death[0]['args'] if w.startswith('population/')], ['population/death:=0.005'])
        # A multiplier scales every rate of its setting; --multipliers replaces the file's list.
        spec = PLAIN + 'population:\n  - {death: 1.0e-4, malfunction: 1.0e-3, repair: 4.0e-3, multiplier: [1, 3]}\n'
        path = write(self.tmp, 'mult.yaml', spec)
        words = [[w for w in r['args'] if w.startswith('population/')]
                 for r in experiment.expand(experiment.load(path)) if r['seed'] == 1 and r['controller'] == 'crw']
        self.assertEqual(words, [['population/death:=0.0001', 'population/malfunction:=0.001', 'population/repair:=0.004'],
                                 ['population/death:=0.0003', 'population/malfunction:=0.003', 'population/repair:=0.012']])
        over = experiment.expand(experiment.load(path, {'population': [8.0]}))
        self.assertEqual({w for r in over for w in r['args'] if w.startswith('population/death')},
                         {'population/death:=0.0008'})
        levels = experiment.expand(experiment.load(write(self.tmp, 'saa2.yaml', SAA), {'noise': [0.0, 0.01, 0.02]}))
        self.assertEqual(len(levels), 3 * len(plain))

    def test_2_bad_axes_are_refused_before_any_run(self):
        """The file's form is refused when read (experiment.load), the values by run_experiment's start-up
        check, which `sweep` runs for every setting before any run (exit 2)."""
        when_read = [
            (PLAIN + 'noise:\n  - {all/levle: 0.01}\n', 'noise[0]: unknown key all/levle'),
            (PLAIN + 'noise:\n  - {gps/level: 0.01}\n', 'noise[0]: unknown key gps/level'),
            (PLAIN + 'noise:\n  - {ground/model: gaussian, ground/level: 0.1}\n', 'ground has no model'),
            (PLAIN + 'noise:\n  - {all/level: [0, 0.01]}\n  - {}\n', 'noise[1] gives the plain run (no noise), '
             'as noise[0] already does'),
            (PLAIN + 'noise:\n  - {all/level: fast}\n', 'noise[0].all/level must be a number'),
            (PLAIN + 'noise: {all/level: 0.01}\n', 'noise must be a list of noise settings'),
            (PLAIN + 'population:\n  - {deaths: 1.0e-4}\n', 'population[0]: unknown key deaths'),
            (PLAIN + 'population:\n  - {death: 1.0e-4, multiplier: [1, 0]}\n', 'population[0].multiplier must be > 0'),
            (PLAIN + 'population:\n  - {death: 1.0e-4}\nparams: {population/repair: 0.1}\n',
             'params.population/repair: the experiment has a population axis'),
            (PLAIN + 'population:\n  - {malfunction: 1.0e-3, repair: 1.0e-3, multiplier: [1, 2]}\n',
             'population[0]: no steady state: lambda = death + malfunction = 0.001 >= mu = birth + repair = 0.001'),
        ]
        for k, (text, message) in enumerate(when_read):
            with self.assertRaises(experiment.ExperimentError, msg='case %d' % k) as caught:
                experiment.load(write(self.tmp, 'read%d.yaml' % k, text))
            self.assertIn(message, str(caught.exception), 'case %d' % k)
        by_sweep = [
            (when_read[0][0], when_read[0][1]),
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
        figures = os.path.join(self.tmp, name + '_figures')
        plot = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'plot_sweep.py'), out, '--output', figures],
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
        points = robustness_tables.read(out)
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
        points = robustness_tables.read(out)
        fams = {(p['family'], p['multiplier']) for p in points}
        self.assertEqual(fams, {(('birth', 'death', 'malfunction', 'repair'), 1.0), (('death',), 1.0)})
        # The records carry world/population: robots leave (deaths, malfunctions) and the count shows it.
        top = [p for p in points if p['family'] == ('death',) and p['controller'] == 'crw'][0]
        active, records = robustness_figures._active_counts(out, 'crw', 8, top['rates'], 1)
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
