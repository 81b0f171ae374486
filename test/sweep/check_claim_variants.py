#!/usr/bin/env python3
"""claim_variants on a tiny ideal sweep (CRW, DPO, GP-DPO at N = 1, 2, 4 in a 32x16 arena, 3 seeds): the
authors' definitions' tables are run_tables' own on the sweep's records, the paper column is the report's
verdict, claim (c) is given arena by arena, and a folder without a sweep is refused by name; R and A per ideal
block divide draw by draw, and A split at the change adds up from DTW computed by hand."""
import filecmp
import json
import os
import subprocess
import sys
import tempfile
import unittest

import rostest
from swarm_forage.study import bootstrap, claim_variants
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SPEC = """name: ideal_32x16
arena: 32x16
controllers: [crw, dpo, gp_dpo]
sizes: {min: 1, max: 4}
runs: 3
ticks: 3000
sample_interval: 1000
"""


def run(cmd, timeout=600):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)


class ClaimVariants(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_claim_variants_'))
        cls.study = os.path.join(cls.tmp, 'study')
        cls.sweep = os.path.join(cls.study, 'ideal_32x16')
        proc = run(['rosrun', 'swarm_forage', 'sweep', write(cls.tmp, 'ideal_32x16.yaml', SPEC), '--out', cls.sweep,
                    '-j', '2'], timeout=900)
        assert proc.returncode == 0, proc.stdout[-3000:]
        cls.output = os.path.join(cls.tmp, 'variants.md')
        cls.proc = run(['rosrun', 'swarm_forage', 'claim_variants', cls.study, '--output', cls.output])
        with open(cls.output) as f:
            cls.text = f.read()

    def test_1_the_authors_tables_are_run_tables_own(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stdout)
        mine = os.path.join(self.tmp, 'direct')
        proc = run(['rosrun', 'swarm_forage', 'run_tables', os.path.join(self.sweep, 'plan'), 'out:=' + mine,
                    'definitions:=authors_code_2019', 'sample_interval:=1000'])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        theirs = os.path.join(self.study, 'variants', 'authors_code_2019', 'ideal_32x16', 'tables')
        for name in ('bootstrap.csv', 'self_organization.csv', 'scalability.csv'):
            self.assertTrue(filecmp.cmp(os.path.join(mine, name), os.path.join(theirs, name), shallow=False), name)
        # The definitions differ where the docs say (Z on final values): the variant is not the paper's table.
        self.assertFalse(filecmp.cmp(os.path.join(theirs, 'self_organization.csv'),
                                     os.path.join(self.sweep, 'tables', 'self_organization.csv'), shallow=False))

    def test_2_the_paper_column_is_the_reports_verdict(self):
        verdicts = os.path.join(self.tmp, 'verdicts.json')
        proc = run([sys.executable, os.path.join(HERE, '..', '..', 'scripts', 'paper_report.py'), '--ideal', self.sweep,
                    '--output', os.path.join(self.tmp, 'report.md'), '--json', verdicts])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(verdicts) as f:
            c = next(x for x in json.load(f) if x['claim'] == 'c')
        row = next(line for line in self.text.splitlines() if line.startswith('| (c) |'))
        cells = [x.strip() for x in row.split('|')[1:-1]]
        self.assertEqual(len(cells), 4, row)
        self.assertTrue(cells[2].startswith('**%s** r = %.3g' % (c['verdict'], c['margin'])), (cells, c))
        for tag in ('b', 'd', 'e1'):  # no 64x32, 96x48 or time-varying sweep here
            row = next(line for line in self.text.splitlines() if line.startswith('| (%s) |' % tag))
            self.assertEqual(row.count('not measured'), 2, row)

    def test_3_claim_c_arena_by_arena(self):
        section = self.text.split('## Claim (c), arena by arena', 1)[1]
        self.assertIn('| 32x16 | **', section)
        self.assertIn('32x16, N = 4: CRW ', section)

    def test_4_a_folder_without_a_sweep_is_refused(self):
        empty = os.path.join(self.tmp, 'empty')
        os.makedirs(empty)
        proc = run(['rosrun', 'swarm_forage', 'claim_variants', empty, '--output', os.path.join(self.tmp, 'x.md')])
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('no ideal or time-varying sweep with tables and a plan in %s' % empty, proc.stdout)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, 'x.md')))

    def test_5_r_and_a_per_ideal_block_divide_draw_by_draw(self):
        tv = bootstrap.Draws()
        ideal, varied = ('64x32', 'crw', 16, 'null', 0.0), ('64x32', 'crw', 16, 'step_down', 0.4)
        tv.values[ideal] = {'P': [10.0, 20.0, 0.0], 'R': [None] * 3, 'A': [None] * 3}
        tv.values[varied] = {'P': [8.0, 9.0, 7.0], 'R': [5.0, 6.0, 7.0], 'A': [2.0, None, 3.0]}
        out = claim_variants.per_ideal_block(tv, 'f')['f']
        self.assertEqual(out.values[varied]['R'], [0.5, 0.3, None])  # no ideal block in draw 2: undefined
        self.assertEqual(out.values[varied]['A'], [0.2, None, None])
        self.assertEqual(out.values[varied]['P'], [8.0, 9.0, 7.0])
        self.assertEqual(tv.values[varied]['A'], [2.0, None, 3.0], 'the input is left as it was')

    def test_6_adaptability_split_at_the_change(self):
        self.assertEqual(claim_variants.dtw([0, 1, 2], [0, 1, 2]), 0.0)
        self.assertEqual(claim_variants.dtw([0, 0, 5], [0, 5, 5]), 0.0)  # warping absorbs the shift
        self.assertEqual(claim_variants.dtw([1, 1], [3, 3]), 4.0)
        folder = os.path.join(self.tmp, 'tv')
        os.makedirs(os.path.join(folder, 'tables'))
        head = 'controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,P_ci95,p_mean\n'
        ideal, varied = [4, 4, 4, 4], [1, 1, 4, 6]  # alpha = 400 s = 2,000 ticks: samples 0 and 1 before it
        rows = ''.join('crw,64x32,16,%s,%s,%s,3,%d,%d,0,0,%g\n' % (w, b, a, i, 1000 * i + 999, v)
                       for w, b, a, series in (('null', 0, 0, ideal), ('step_down', 0.4, 400, varied))
                       for i, v in enumerate(series))
        write(os.path.join(folder, 'tables'), 'series.csv', head + rows)
        write(os.path.join(folder, 'tables'), 'flexibility.csv', 'controller,arena,waveform,beta,N,A\n'
              'crw,64x32,step_down,0.4,16,7.5\n')
        whole = claim_variants.dtw(ideal, varied)
        self.assertEqual(claim_variants.adaptability_halves(folder),
                         {('crw', 16, 0.4): (7.5, whole, 6.0, 2.0)})


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'claim_variants', ClaimVariants)
