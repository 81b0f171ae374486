"""The experiment files' robustness axes (swarm_forage.robustness.axes through experiment.file): noise and
population settings expand into runs whose plain settings keep the keys of runs without the axes, a bad axis is
refused when the file is read, and the report's robustness verdict follows its criterion on hand-made tables.
No runs and no master: the sweeps themselves are test/sweep/robustness_sweep.test."""
import csv
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from sweep_helpers import experiment_text  # noqa: E402
from tmp_files import removed_at_exit, write  # noqa: E402

from swarm_forage.experiment import ExperimentError  # noqa: E402
from swarm_forage.experiment import file as experiment_file  # noqa: E402
from swarm_forage.experiment.plan import expand  # noqa: E402
from swarm_forage.robustness import report, tables  # noqa: E402

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


class RobustnessAxes(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_robustness_axes_'))

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
                 report.verdicts(tables.read(clear), 'saa', label)}
        self.assertEqual(found[16][:3], ('CRW degrades least', 'crw', ['level 0.01 (all/level)']))
        self.assertEqual(found[16][3], {'level 0.02 (all/level)': 'DPO: no reference'})
        self.assertEqual(found[64][1], None)
        self.assertIn('no clear winner: CRW and DPO', found[64][0])
        self.assertIn('cannot tell: one seed', found[256][0])
        lines, summary = report.section([clear], label)
        self.assertIn(('clear, SAA, 32x16, N = 16', 'CRW degrades least'), summary)
        self.assertIn('| 32x16 | 16 | d 1.1 ± 0.25 (3 seeds); P -10.0 % | d 5.1 ± 0.25 (3 seeds); P -10.0 % | '
                      'CRW degrades least |', lines)

    def test_1_axes_expand_into_runs_and_plain_runs_keep_their_keys(self):
        plain = expand(experiment_file.load(write(self.tmp, 'saa_plain.yaml', SAA_PLAIN)))
        saa = expand(experiment_file.load(write(self.tmp, 'saa.yaml', SAA)))
        self.assertEqual(len(saa), 2 * len(plain))
        noisy = [r for r in saa if r['noise']]
        self.assertEqual(len(noisy), len(plain))
        for r in noisy:
            self.assertIn('noise/all/level:=0.03', r['args'])
            self.assertIn('noise/all/model:=gaussian', r['args'])
            self.assertIn('_saa-all-gaussian0.03_', r['key'])
        # Level 0 is the plain run: no noise words, the key of the same run without the axis.
        self.assertEqual(sorted(r['key'] for r in saa if not r['noise']), sorted(r['key'] for r in plain))
        plain = expand(experiment_file.load(write(self.tmp, 'plain.yaml', PLAIN)))
        pd = expand(experiment_file.load(write(self.tmp, 'pd.yaml', PD)))
        self.assertEqual(len(pd), 3 * len(plain))
        death = [r for r in pd if r['population'] == 'pd-d0.005']
        self.assertEqual(len(death), len(plain))
        self.assertEqual([w for w in death[0]['args'] if w.startswith('population/')], ['population/death:=0.005'])
        # A multiplier scales every rate of its setting; --multipliers replaces the file's list.
        spec = PLAIN + 'population:\n  - {death: 1.0e-4, malfunction: 1.0e-3, repair: 4.0e-3, multiplier: [1, 3]}\n'
        path = write(self.tmp, 'mult.yaml', spec)
        words = [[w for w in r['args'] if w.startswith('population/')]
                 for r in expand(experiment_file.load(path)) if r['seed'] == 1 and r['controller'] == 'crw']
        self.assertEqual(words, [['population/death:=0.0001', 'population/malfunction:=0.001', 'population/repair:=0.004'],
                                 ['population/death:=0.0003', 'population/malfunction:=0.003', 'population/repair:=0.012']])
        over = expand(experiment_file.load(path, {'population': [8.0]}))
        self.assertEqual({w for r in over for w in r['args'] if w.startswith('population/death')},
                         {'population/death:=0.0008'})
        levels = expand(experiment_file.load(write(self.tmp, 'saa2.yaml', SAA), {'noise': [0.0, 0.01, 0.02]}))
        self.assertEqual(len(levels), 3 * len(plain))

    def test_2_bad_axes_are_refused_when_the_file_is_read(self):
        """The file's form is refused when read (experiment_file.load); the values are refused by run_experiment's
        start-up check, which `sweep` runs before any run (test/sweep/robustness_sweep.test)."""
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
            with self.assertRaises(ExperimentError, msg='case %d' % k) as caught:
                experiment_file.load(write(self.tmp, 'read%d.yaml' % k, text))
            self.assertIn(message, str(caught.exception), 'case %d' % k)


if __name__ == '__main__':
    unittest.main()
