#!/usr/bin/env python3
"""Verdicts with confidence (issue 24): a claim within noise comes out undecided with the seeds that would
decide it, a clear one agrees or disagrees, fewer than 3 seeds never decide, Spearman's rho handles ties, and
paper_report.py writes the margins, intervals, seeds, thresholds and the JSON `paper --decide` reads."""
import json
import os
import random
import subprocess
import sys
import tempfile
import unittest

import rostest
from graph_helpers import removed_at_exit, write

from swarm_forage import claims, paper_claims

HEAD = 'draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A,sample_interval,identity\n'
SERIES_HEAD = ('controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,P_ci95,p_mean,p_ci95,'
               'n_ca_mean,n_ca_ci95,sample_interval,identity\n')
REPORT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'scripts', 'paper_report.py')


def sweep_folder(root, name, groups, draws=400, seed=1):
    """A sweep folder with tables/bootstrap.csv and series.csv of ideal 96x48 groups: groups maps (controller,
    N) -> the per-seed final P; each draw resamples the seeds, as run_tables does."""
    folder = os.path.join(root, name)
    os.makedirs(os.path.join(folder, 'tables'))
    rng = random.Random(seed)
    rows, series = [], []
    for (c, n), values in sorted(groups.items()):
        ident = '%08x' % (hash((c, n)) & 0xffffffff)
        for d in range(draws + 1):
            picked = values if d == 0 else [rng.choice(values) for _ in values]
            rows.append('%d,%s,96x48,null,0,"null",%d,%d,%.17g,,,,,1000,%s\n' % (d, c, n, len(values),
                                                                                  sum(picked) / len(picked), ident))
        series.append('%s,96x48,%d,null,0,0,%d,49,49999,%.10g,0,0,0,0,0,1000,%s\n' % (
            c, n, len(values), sum(values) / len(values), ident))
    write(os.path.join(folder, 'tables'), 'bootstrap.csv', HEAD + ''.join(rows))
    write(os.path.join(folder, 'tables'), 'series.csv', SERIES_HEAD + ''.join(series))
    return folder


def claim(folder, tag):
    return next(c for c in paper_claims.evaluate([folder], None, str)[0] if c.tag == tag)


class Claims(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_claims_'))

    def test_1_a_claim_within_noise_is_undecided_with_the_seeds_that_would_decide_it(self):
        # DPO 2,048 is 14 % under CRW 8,192 on average, with a spread that makes 10 % and 20 % both plausible.
        crw = [990, 1010, 1000, 1020, 980, 1000]  # mean 1,000
        dpo = [700, 1000, 850, 950, 750, 910]      # mean 860: q = 0.14, standard error about 0.05
        c = claim(sweep_folder(self.tmp, 'noisy', {('crw', 8192): crw, ('dpo', 2048): dpo}), 'd')
        self.assertEqual(c.verdict, 'undecided', vars(c))
        self.assertLess(c.low, claims.WITHIN)
        self.assertGreater(c.high, claims.WITHIN)
        self.assertGreater(c.seeds_needed, 6)
        self.assertEqual(sorted(set(c.seeds.values())), [6])

    def test_2_clear_claims_are_decided_both_ways(self):
        crw = [1000, 1010, 990, 1005, 995]
        near = claim(sweep_folder(self.tmp, 'near', {('crw', 8192): crw, ('dpo', 2048): [960, 970, 950, 965, 955]}),
                     'd')
        self.assertEqual(near.verdict, 'agrees', vars(near))
        far = claim(sweep_folder(self.tmp, 'far', {('crw', 8192): crw, ('dpo', 2048): [400, 500, 450, 420, 480]}),
                    'd')
        self.assertEqual(far.verdict, 'disagrees', vars(far))
        self.assertAlmostEqual(far.estimate, 1 - 450 / 1000.0, places=9)
        self.assertIsNone(far.seeds_needed)

    def test_3_two_seeds_never_decide(self):
        c = claim(sweep_folder(self.tmp, 'two', {('crw', 8192): [1000, 1001], ('dpo', 2048): [400, 401]}), 'd')
        self.assertEqual(c.verdict, 'undecided')
        self.assertEqual(c.seeds_needed, claims.MIN_SEEDS)

    def test_4_spearman_ranks_ties_by_their_mean(self):
        # y ranks with ties: [3.5, 3.5, 2, 1] against x ranks [1, 2, 3, 4]: r = -4.5 / sqrt(5 * 4.5) = -0.9487
        self.assertAlmostEqual(claims.spearman([0.1, 0.2, 0.4, 0.8], [5, 5, 3, 1]), -4.5 / (5 * 4.5) ** 0.5, places=12)
        # order of the tied pair does not matter (a rank-in-input-order rho would give -0.8 one way, -1 the other)
        self.assertAlmostEqual(claims.spearman([0.2, 0.1, 0.4, 0.8], [5, 5, 3, 1]),
                               claims.spearman([0.1, 0.2, 0.4, 0.8], [5, 5, 3, 1]), places=12)
        self.assertEqual(claims.ranks([2, 1, 2, 2]), [3.0, 1.0, 3.0, 3.0])

    def test_5_report_shows_margin_interval_seeds_threshold_and_writes_the_json(self):
        crw = [1000, 1010, 990, 1005, 995]
        folder = sweep_folder(self.tmp, 'report', {('crw', 8192): crw, ('dpo', 2048): [400, 500, 450, 420, 480],
                                                   ('crw', 16384): [1500, 1490, 1510], ('dpo', 16384): [700, 720, 710]})
        out, js = os.path.join(self.tmp, 'report.md'), os.path.join(self.tmp, 'verdicts.json')
        proc = subprocess.run([sys.executable, REPORT, '--ideal', folder, '--claims', 'c,d', '--output', out,
                               '--json', js], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        text = open(out).read()
        self.assertIn('| (d) | q <= 0.15 | 0.550 | [', text)
        self.assertIn('| 5 | disagrees |', text)
        self.assertIn('| (c) | r > 0 |', text)
        self.assertIn('the 15 % tolerance (0.150): the measured quantity is 0.550', text)
        self.assertNotIn('(a1)', text)
        verdicts = {v['claim']: v for v in json.load(open(js))}
        self.assertEqual(sorted(verdicts), ['c', 'd'])
        self.assertEqual(verdicts['d']['verdict'], 'disagrees')
        self.assertEqual(verdicts['c']['verdict'], 'agrees')
        self.assertIn([folder, '96x48', 'dpo', 2048, 'null', 0.0], verdicts['d']['groups'])

    def test_6_an_unfinished_sweep_is_refused_unless_partial(self):
        folder = sweep_folder(self.tmp, 'unfinished', {('crw', 8192): [1000, 1010, 990], ('dpo', 2048): [400, 500, 450]})
        write(folder, 'runs.tsv', 'a\tseed:=1\nb\tseed:=2\nc\tseed:=3\n')  # the plan: three runs, one recorded
        os.makedirs(os.path.join(folder, 'runs'))
        write(os.path.join(folder, 'runs'), 'b.bag', '')
        out = os.path.join(self.tmp, 'unfinished.md')
        proc = subprocess.run([sys.executable, REPORT, '--ideal', folder, '--claims', 'c,d', '--output', out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(proc.returncode, 1, proc.stdout)
        self.assertIn('%s: 2 of 3 planned records missing' % folder, proc.stdout)
        self.assertIn('--partial', proc.stdout)
        self.assertFalse(os.path.exists(out))
        proc = subprocess.run([sys.executable, REPORT, '--ideal', folder, '--claims', 'c,d', '--output', out,
                               '--partial'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('**Partial:** these sweeps have not finished', open(out).read())
        self.assertIn('2 of 3 planned records missing', open(out).read())
        # Every planned record there: a finished sweep, reported without the flag and without the mark.
        for key in 'ac':
            write(os.path.join(folder, 'runs'), key + '.bag', '')
        proc = subprocess.run([sys.executable, REPORT, '--ideal', folder, '--claims', 'c,d', '--output', out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertNotIn('Partial', open(out).read())


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'claims', Claims)
