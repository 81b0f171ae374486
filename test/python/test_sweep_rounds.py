"""The rule of a sweep's rounds of seeds (swarm_forage.sweep.rounds): on hand-built values where the Student
t interval and the bootstrap disagree the rule follows the bootstrap, and `paper --decide`'s choice of seeds on
a stub of paper_report.py's --json. No runs and no master: the rounds through `sweep` are
test/sweep/sweep_precision.test."""
import math
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from tmp_files import removed_at_exit, write  # noqa: E402

from swarm_forage.sweep import rounds as rr  # noqa: E402

# t(0.975, 2): what a Student t interval of three seeds would use (test 1 shows the rule does not)
T975_2 = 4.30265273


class SweepRounds(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_rounds_'))

    def test_1_the_rule_of_the_rounds(self):
        # Hand-built: seeds of final P 100, 100 and 130; bootstrap.csv holds every one of the 27 resamples.
        # The bootstrap's 95 % interval is [100, 123.5], within 12.3 % of the mean 110; a Student t interval
        # would be 110 +- 43.0 (39 %). At a precision of 20 % the group is precise by the bootstrap, and would
        # not be by the t interval.
        seeds, precision = [100.0, 100.0, 130.0], 0.2
        folder = os.path.join(self.tmp, 'hand')
        os.makedirs(os.path.join(folder, 'tables'))
        draws = [seeds] + [[seeds[i], seeds[j], seeds[k]] for i in range(3) for j in range(3) for k in range(3)]
        write(os.path.join(folder, 'tables'), 'bootstrap.csv',
              'draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A,sample_interval,identity\n' +
              ''.join('%d,crw,10x5,null,0,"null",8,3,%.17g,,,,,1000,0000abcd\n' % (d, sum(v) / 3)
                      for d, v in enumerate(draws)))
        p = rr.final_intervals(folder)['0000abcd']
        self.assertEqual((p.estimate, p.seeds), (110.0, 3))
        self.assertAlmostEqual(p.lo, 100.0)
        self.assertAlmostEqual(p.hi, 123.5)  # 0.975 x 26 = 25.35: 120 + 0.35 x (130 - 120)
        sd = math.sqrt(sum((v - 110.0) ** 2 for v in seeds) / 2)
        t_half = T975_2 * sd / math.sqrt(3)
        self.assertGreater(t_half, precision * 110.0)  # the t interval would ask for more seeds
        row = {'group': 'crw_n8_null', 'runs': str(p.seeds), 'P_mean': repr(p.estimate), 'P_low': repr(p.lo),
               'P_high': repr(p.hi)}
        self.assertEqual(rr.judge([row], precision, 6)['crw_n8_null'][0], 'precise')
        self.assertAlmostEqual(rr.judge([row], precision, 6)['crw_n8_null'][3], 13.5)
        self.assertEqual(rr.judge([row], 0.1, 6)['crw_n8_null'][:2], ('more', 3))
        one = rr.judge([dict(row, runs='1', P_low='', P_high='')], 0.1, 6)['crw_n8_null']
        self.assertEqual((one[0], one[1], one[4]), ('more', 1, 2))  # one seed: no interval, one more
        self.assertFalse(rr.precise(1, 10.0, 0.0, 0.05))  # one seed: no interval
        self.assertTrue(rr.precise(3, 0.0, 0.0, 0.05))  # every seed delivered nothing
        self.assertTrue(rr.precise(3, 100.0, 5.0, 0.05))
        self.assertFalse(rr.precise(3, 100.0, 5.01, 0.05))
        self.assertEqual(rr.normal_count(3, 100.0, 10.0, 0.05), 12)  # 3 x (10 / 5)^2
        self.assertEqual(rr.next_count(3, 12, 50), 12)
        self.assertEqual(rr.next_count(3, 2, 50), 4)  # at least one more
        self.assertEqual(rr.next_count(3, 400, 50), 50)  # at most the cap

    def test_2_decide_raises_the_undecided_claims_groups(self):
        """paper --decide's choice on a stub of paper_report.py --json and hand-made groups.tsv listings."""
        a, b = os.path.join(self.tmp, 'ideal_a'), os.path.join(self.tmp, 'tv_b')
        row = lambda g, c, n, w, beta, runs: dict(group=g, controller=c, N=str(n), waveform=w, beta=beta, noise='',
                                                  population='', runs=str(runs))  # noqa: E731
        listings = {os.path.realpath(a): [row('crw_n8_null', 'crw', 8, 'null', '0', 3),
                                          row('dpo_n8_null', 'dpo', 8, 'null', '0', 3),
                                          row('dpo_n2_null', 'dpo', 2, 'null', '0', 10)],
                    os.path.realpath(b): [row('crw_n8_step_down0.4', 'crw', 8, 'step_down', '0.4', 2),
                                          row('crw_n8_step_down0.8', 'crw', 8, 'step_down', '0.8', 2)]}
        caps = {os.path.realpath(a): 10, os.path.realpath(b): 5}
        claims = [
            {'claim': 'a', 'verdict': 'agrees', 'margin': 1.0, 'low': 0.5, 'high': 1.5, 'seeds_needed': None,
             'groups': [[a, '10x5', 'crw', 8, 'null', 0]]},
            {'claim': 'd', 'verdict': 'undecided', 'margin': 0.1, 'low': -0.2, 'high': 0.4, 'seeds_needed': 7,
             'groups': [[a, '10x5', 'crw', 8, 'null', 0], [a, '10x5', 'dpo', 8, 'null', 0],
                        [a, '10x5', 'dpo', 2, 'null', 0]]},
            {'claim': 'e1', 'verdict': 'undecided', 'margin': 0.1, 'low': -0.2, 'high': 0.4, 'seeds_needed': None,
             'groups': [[b, '64x32', 'crw', 8, 'step_down', 0.4]]},
            {'claim': 'e2', 'verdict': 'undecided', 'margin': 0.1, 'low': -0.2, 'high': 0.4, 'seeds_needed': 40,
             'groups': [[b, '64x32', 'crw', 8, 'step_down', 0.8]]},
            {'claim': 'c', 'verdict': 'not measured', 'margin': None, 'low': None, 'high': None,
             'seeds_needed': None, 'groups': []},
        ]
        raises, lines = rr.decide(claims, listings, caps)
        self.assertEqual(raises, {os.path.realpath(a): {'crw_n8_null': 7, 'dpo_n8_null': 7},
                                  os.path.realpath(b): {'crw_n8_step_down0.4': 4, 'crw_n8_step_down0.8': 5}})
        self.assertEqual(len(lines), 3, lines)
        self.assertIn('(d) undecided', lines[0])
        self.assertIn('crw_n8_null 3 -> 7', lines[0])
        # At the cap: nothing left to raise, the loop ends.
        capped = [dict(c, groups=[[a, '10x5', 'dpo', 2, 'null', 0]]) for c in claims[1:2]]
        raises, lines = rr.decide(capped, listings, caps)
        self.assertEqual(raises, {})
        self.assertIn('every group at its cap (dpo_n2_null)', lines[0])
        self.assertEqual(rr.decide(claims[:1] + claims[4:], listings, caps), ({}, []))
        with self.assertRaisesRegex(ValueError, 'which sweep .* has not'):
            rr.decide([dict(claims[1], groups=[[a, '10x5', 'gp_dpo', 8, 'null', 0]])], listings, caps)
        with self.assertRaisesRegex(ValueError, 'did not run'):
            rr.decide([dict(claims[1], groups=[['/nowhere', '10x5', 'crw', 8, 'null', 0]])], listings, caps)


if __name__ == '__main__':
    unittest.main()
