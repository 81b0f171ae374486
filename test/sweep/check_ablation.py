#!/usr/bin/env python3
"""The ablation through the one study engine: an experiment file's `models` axis expands into one group per
quirk set with distinct identities (and refuses what would run a setting twice), a tiny ablation (two arms in a
10x5 arena, 3,000 ticks, 3 seeds, 2 rows) runs through `sweep`, and ablation_table.py makes its table from the
sweeps' tables: every final P interval and claim (d) from the bootstrap over seeds (checked against
bootstrap.csv with this file's own arithmetic), the stalled count from the records' last swarm/status."""
import csv
import glob
import os
import re
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import percentile  # noqa: E402

from swarm_forage.experiment import ExperimentError, models
from swarm_forage.experiment import file as experiment_file
from swarm_forage.experiment.plan import expand

HERE = os.path.dirname(os.path.abspath(__file__))
ARENA = os.path.join(HERE, '..', 'fixtures', 'arena_10x5.yaml')
TABLE = os.path.join(HERE, '..', '..', 'scripts', 'ablation_table.py')
ROWS = ['swarm_forage', 'fordyca_2019']
ARM = """name: %s
arena: %s
controllers: [%s]
sizes: [%d]
runs: 3
ticks: 3000
sample_interval: 1000
models: [swarm_forage, fordyca_2019]
"""
WITHIN = 0.15  # claim (d): within 15 %


def bootstrap_rows(folder):
    """{identity: [P of draw 0, 1, ..., B]} of a sweep's tables/bootstrap.csv."""
    out = {}
    with open(os.path.join(folder, 'tables', 'bootstrap.csv')) as f:
        for r in csv.DictReader(f):
            column = out.setdefault(r['identity'], [])
            while len(column) <= int(r['draw']):
                column.append(None)
            column[int(r['draw'])] = float(r['P'])
    return out


def record(path):
    """(run_info, final P, robots stalled at the last tick) of a record, read here without the package."""
    with rosbag.Bag(path) as bag:
        info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
        final = [m for _, m, _ in bag.read_messages(topics=['/world/performance'])][-1].cumulative
        status = [m for _, m, _ in bag.read_messages(topics=['/swarm/status'])]
    last = max(m.tick for m in status)
    return info, final, sum(m.stalled for m in status if m.tick == last)


class Ablation(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_ablation_'))

    def test_1_the_models_axis_expands_into_one_group_per_quirk_set(self):
        listing = models.models()
        quirks = [q['name'] for q in listing['quirks']]
        fordyca = {q['name'] for q in listing['quirks'] if q['fordyca_2019']}
        left_out = [q for q in quirks if q not in fordyca]
        spec = write(self.tmp, 'axis.yaml', ARM.replace('models: [swarm_forage, fordyca_2019]',
                                                        'models: [swarm_forage, fordyca_2019, swarm_forage+each, '
                                                        'fordyca_2019+each]') % ('axis', ARENA, 'dpo', 4))
        exp = experiment_file.load(spec)
        names = [m['name'] for m in exp['models']]
        self.assertEqual(names, ['swarm_forage', 'fordyca_2019'] + ['swarm_forage+' + q for q in quirks] +
                         ['fordyca_2019+' + q for q in left_out])
        runs = expand(exp)
        self.assertEqual(len(runs), 3 * len(names))
        first = [r for r in runs if r['seed'] == 1]
        self.assertEqual([r['setting'] for r in first], names)
        # Distinct groups, keys and identities: no two quirk sets share a record.
        for field in ('group', 'key', 'identity'):
            self.assertEqual(len({r[field] for r in first}), len(names), field)
        self.assertEqual(len({r['key'] for r in runs}), len(runs))
        # Each run's words give its quirk set, whichever model is the default.
        for r in first:
            words = dict(w.split(':=', 1) for w in r['args'])
            got = models.model_quirks(words.get('model', listing['default'])) | \
                {q for q in words.get('quirks', '').split(',') if q}
            model, _, extra = r['setting'].partition('+')
            self.assertEqual(got, models.model_quirks(model) | ({extra} if extra else set()), r['args'])
            self.assertEqual(models.model_name(got), r['setting'])
        # The same setting written as a map; --models replaces the axis.
        as_map = experiment_file.load(write(self.tmp, 'map.yaml', ARM.replace(
            'models: [swarm_forage, fordyca_2019]', 'models:\n  - {model: fordyca_2019, quirks: each}\n'
            '  - {model: swarm_forage, quirks: [heading_estimate]}\n') % ('map', ARENA, 'dpo', 4)))
        self.assertEqual([m['name'] for m in as_map['models']],
                         ['fordyca_2019+' + q for q in left_out] + ['swarm_forage+heading_estimate'])
        over = experiment_file.load(spec, {'models': 'fordyca_2019,swarm_forage+light_occlusion'})
        self.assertEqual([m['name'] for m in over['models']], ['fordyca_2019', 'swarm_forage+light_occlusion'])
        # What would run a setting twice, or cannot be run, is refused with the reason.
        plain = ARM.replace('models: [swarm_forage, fordyca_2019]\n', '') % ('bad', ARENA, 'dpo', 4)
        for text, message in (
                ('models: [fordyca_2019+transport_wander]\n', 'fordyca_2019 already has transport_wander'),
                ('models: [swarm_forage+nope]\n', "'nope' is not a quirk; valid: "),
                ('models: [fordyca, swarm_forage]\n', "'fordyca' is unknown; valid: fordyca_2019, swarm_forage"),
                ('models: [swarm_forage, swarm_forage]\n', 'the same quirks as swarm_forage already gives'),
                ('models: [fordyca_2019, swarm_forage+%s]\n' % '+'.join(sorted(fordyca)),
                 'the same quirks as fordyca_2019 already gives'),
                ('models: []\n', 'models must be the model as an axis'),
                ('models: [{quirks: [light_occlusion]}]\n', 'model is missing'),
                ('models: [swarm_forage]\nmodel: fordyca_2019\n', 'models (the model as an axis) goes without model')):
            with self.assertRaises(ExperimentError) as err:
                experiment_file.load(write(self.tmp, 'bad.yaml', plain + text))
            self.assertIn(message, str(err.exception), text)
        with self.assertRaisesRegex(ExperimentError, 'has a models axis: replace it with --models'):
            experiment_file.load(spec, {'model': 'fordyca_2019'})
        proc = subprocess.run(['rosrun', 'swarm_forage', 'sweep', spec, '--models', 'fordyca_2019', '--quirks',
                               'light_occlusion', '--dry-run'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=120)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('--models goes without --model and --quirks', proc.stdout)
        proc = subprocess.run(['rosrun', 'swarm_forage', 'paper', '--ablation', '--model', 'fordyca_2019',
                               '--dry-run'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('--ablation goes without', proc.stdout)

    def test_2_a_tiny_ablation_through_sweep_and_its_table(self):
        arms = [('tiny_dpo', 'dpo', 4), ('tiny_crw', 'crw', 8)]
        folders = []
        for name, controller, n in arms:
            out = os.path.join(self.tmp, name)
            folders.append(out)
            proc = subprocess.run(['rosrun', 'swarm_forage', 'sweep', write(self.tmp, name + '.yaml', ARM % (
                name, ARENA, controller, n)), '--out', out, '-j', '2'], stdout=subprocess.PIPE,
                stderr=subprocess.STDOUT, text=True, timeout=900)
            self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
            self.assertIn('x 2 models', proc.stdout)
            # The calibration times each model apart (the quirks change a tick's cost).
            line = next(x for x in proc.stdout.splitlines() if ': calibration: ' in x)
            self.assertEqual(len(re.findall(r'\b%s\b' % controller, line.split('robot-ticks/s')[0])), 2, line)
        table, runs_csv = os.path.join(self.tmp, 'table.md'), os.path.join(self.tmp, 'runs.csv')
        proc = subprocess.run([TABLE] + folders + ['--output', table, '--csv', runs_csv, '--claim-d-sizes',
                                                   '10x5,4,8'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(table) as f:
            text = f.read()
        lines = {line.split('|')[1].strip(): line for line in text.splitlines() if line.startswith('| ')}
        self.assertEqual(sorted(k for k in lines if k != 'row'), sorted(ROWS), text)
        self.assertIn('DPO 10×5 N=4: final P', lines['row'])
        self.assertIn('CRW 10×5 N=8: final P', lines['row'])
        with open(runs_csv) as f:
            per_run = list(csv.DictReader(f))
        self.assertEqual(len(per_run), 12, per_run)
        finals = {}  # (row, controller) -> (identity, [final P], [stalled])
        for folder, (_, controller, n) in zip(folders, arms):
            draws = bootstrap_rows(folder)
            for path in glob.glob(os.path.join(folder, 'plan', '*.bag')):
                info, final, stalled = record(path)
                row = 'fordyca_2019' if 'light_occlusion' in info.world_constants else 'swarm_forage'
                ident, p, st = finals.setdefault((row, controller), (info.identity, [], []))
                self.assertEqual(ident, info.identity, 'one identity per row and arm')
                p.append(final)
                st.append(stalled)
                line = next(r for r in per_run if r['record'] == os.path.basename(path))
                self.assertEqual((line['row'], int(line['seed']), float(line['final_P']), int(line['stalled'])),
                                 (row, info.seed, final, stalled))
            for row in ROWS:
                ident, p, st = finals[(row, controller)]
                column = draws[ident]
                mean = sum(p) / len(p)
                self.assertAlmostEqual(column[0], mean, places=6)
                lo, hi = percentile(column[1:], 0.025), percentile(column[1:], 0.975)
                cell = '%.1f [%.1f, %.1f] (%.0f–%.0f)' % (mean, max(0.0, lo), max(0.0, hi), min(p), max(p))
                self.assertIn(cell, lines[row], 'final P of %s %s: bootstrap interval from bootstrap.csv' % (
                    row, controller))
                self.assertIn('| %.1f (%d–%d) |' % (sum(st) / len(st), min(st), max(st)), lines[row])
        self.assertNotEqual(finals[('swarm_forage', 'dpo')][0], finals[('fordyca_2019', 'dpo')][0])
        # Claim (d) per row, q = |P(DPO) - P(CRW)| / P(CRW) draw by draw over the same bootstrap.
        dpo_draws, crw_draws = bootstrap_rows(folders[0]), bootstrap_rows(folders[1])
        for row in ROWS:
            d, c = dpo_draws[finals[(row, 'dpo')][0]], crw_draws[finals[(row, 'crw')][0]]
            self.assertEqual(len(d), len(c))
            q = [abs(a - b) / b for a, b in zip(d, c) if b > 0]
            self.assertEqual(len(q), len(d), 'CRW delivered in every draw')
            lo, hi = percentile(q[1:], 0.025), percentile(q[1:], 0.975)
            verdict = 'agrees' if hi <= WITHIN else 'disagrees' if lo > WITHIN else 'undecided'
            self.assertIn('| %.3f [%.3f, %.3f] | %s |' % (q[0], lo, hi, verdict), lines[row])
            self.assertIn('(d) %s: %s' % (row, verdict), proc.stdout)
        self.assertIn('95 % bootstrap interval over seeds', text)
        self.assertIn('The runs were made by the code', text)

        # A sweep that has not finished (a planned run without its record) is refused, or tabled with --partial,
        # which says so.
        plan = os.path.join(folders[1], 'runs.tsv')
        with open(plan) as f:
            planned = f.read()
        first = planned.splitlines()[0].split('\t')
        more = [re.sub(r'_seed1_', '_seed4_', first[0])] + [w.replace('seed:=1', 'seed:=4') for w in first[1:]]
        try:
            with open(plan, 'a') as f:
                f.write('\t'.join(more) + '\n')
            proc = subprocess.run([TABLE] + folders + ['--output', table], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=300)
            self.assertEqual(proc.returncode, 1, proc.stdout)
            self.assertIn('1 of 7 planned records missing', proc.stdout)
            proc = subprocess.run([TABLE] + folders + ['--output', table, '--partial'], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=300)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            with open(table) as f:
                self.assertIn('**Partial:**', f.read())
        finally:
            with open(plan, 'w') as f:
                f.write(planned)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'ablation', Ablation)
