#!/usr/bin/env python3
"""SAA and population-dynamics robustness from real bags: run_tables' robustness.csv against values computed
here by hand from the runs' series, under paper, authors_code_2020 and authors_code, and the live
metrics/robustness of a `rosbag play` equal to the table to the last bit.

Two real runs (run_experiment, seeds 1 and 2) are recorded. The library holds seed 1 as it is (the reference),
a real run of seed 1 with noise on every device (noise/all/level), and copies of seed 2's recording whose
RunInfo carries noise/ or population/ words and seed 1: hand-made bags of runs with noise and population
dynamics, whose curves differ from the reference's as such a run's would (stable rates x1 and x2, an
unstable queue and death only)."""
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rospy
import rostest
from swarm_forage.msg import Robustness
from swarm_forage.bags.runs import read_run
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit  # noqa: E402

# ---- The test's own reading of the robustness words and the time out of the swarm, written apart from the
# ---- core (core/metrics/robustness.cpp) so that the tables are checked against an independent computation.

POPULATION_RATES = ("death", "birth", "malfunction", "repair")


def robustness_words(world_constants):
    """What a run's world constants (RunInfo.world_constants) say about noise and population dynamics, read as
    robustnessWords() in the core reads them: dict with noise (its noise/ words, space-separated), noise_level
    (the largest level over its devices), devices (their names), death, birth, malfunction, repair (per tick),
    max_size, without_noise and without_population (the words left: the references' world constants) and
    problem ('' or the first word that cannot be read)."""
    out = {"noise": [], "noise_level": 0.0, "devices": [], "max_size": 0, "without_noise": [],
           "without_population": [], "problem": ""}
    out.update({r: 0.0 for r in POPULATION_RATES})

    def number(text):
        try:
            v = float(text)
        except ValueError:
            return None
        return v if math.isfinite(v) and v >= 0 else None

    for word in world_constants.split():
        name, _, value = word.partition("=")
        noise, population = name.startswith("noise/"), name.startswith("population/")
        if not noise:
            out["without_noise"].append(word)
        if not population:
            out["without_population"].append(word)
        if noise:
            out["noise"].append(word)
            out["devices"].append(name[len("noise/"):])
            level = number(value.rpartition(":")[2])
            if level is None:
                out["problem"] = out["problem"] or "cannot read the noise level of '%s'" % word
            else:
                out["noise_level"] = max(out["noise_level"], level)
        elif population:
            key, v = name[len("population/"):], number(value)
            if v is None or key not in POPULATION_RATES + ("max_size",):
                out["problem"] = out["problem"] or "cannot read the population word '%s'" % word
            else:
                out[key] = int(v) if key == "max_size" else v
    for k in ("noise", "without_noise", "without_population"):
        out[k] = " ".join(out[k])
    return out


def queue_time(rates, definitions="paper", T=None):
    """(value, reason) of the expected ticks a robot spends out of the swarm, as expectedTimeOut() in the core:
    paper 1/(mu - lambda) - 1/mu; authors_code 1/(mu - lambda), or T under pure death (death > 0, birth = 0);
    value None with the reason when there is no steady state (lambda >= mu) or no dynamics. `rates`: a dict
    with death, birth, malfunction, repair (robustness_words gives one)."""
    if definitions == "authors_code_2019":
        return None, "authors_code_2019: the authors' 2019 code has no robustness measure"
    lam = rates["death"] + rates["malfunction"]
    mu = rates["birth"] + rates["repair"]
    if lam == 0 and mu == 0:
        return None, "no population dynamics (every rate is 0)"
    if definitions == "authors_code" and rates["death"] > 0 and rates["birth"] == 0:
        return T, ""
    if not lam < mu:
        return None, ("no steady state: lambda = death + malfunction = %g >= mu = birth + repair = %g per tick"
                      % (lam, mu))
    w = 1.0 / (mu - lam)
    return (w - 1.0 / mu if definitions == "paper" else w), ""


TICKS = 3000
INTERVAL = 500
NOISE = 'noise/proximity=gaussian:0.01 noise/wheels=uniform:0.02'
PD1 = ('population/death=0.0001 population/birth=0.0005 population/malfunction=0.001 population/repair=0.002 '
       'population/max_size=8')
PD2 = ('population/death=0.0002 population/birth=0.001 population/malfunction=0.002 population/repair=0.004 '
       'population/max_size=8')
UNSTABLE = ('population/death=0 population/birth=0 population/malfunction=0.003 population/repair=0.002 '
            'population/max_size=8')
DEATH = ('population/death=0.0003 population/birth=0 population/malfunction=0 population/repair=0 '
         'population/max_size=8')


def sigma(x):
    return 1.0 / (1.0 + math.exp(-x))


def dtw(a, b, cost):
    """Exact DTW, the textbook recurrence (independent of the C++ one)."""
    inf = float('inf')
    d = [[inf] * (len(b) + 1) for _ in range(len(a) + 1)]
    d[0][0] = 0.0
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = cost(i - 1, j - 1) + min(d[i - 1][j], d[i][j - 1], d[i - 1][j - 1])
    return d[len(a)][len(b)]


def with_words(src, dst, words, seed):
    """A copy of the bag `src` whose run_info carries `words` more and `seed`."""
    with rosbag.Bag(src) as inp, rosbag.Bag(dst, 'w') as out:
        for topic, msg, t in inp.read_messages():
            if topic.endswith('world/run_info'):
                msg.world_constants += ' ' + words
                msg.seed = seed
            out.write(topic, msg, t)


def rows(folder, name):
    with open(os.path.join(folder, name)) as f:
        return list(csv.DictReader(f))


class TestRobustnessMetrics(unittest.TestCase):
    def test_tables_and_live(self):
        rospy.init_node('check_robustness_metrics')
        library = removed_at_exit(rospy.get_param('~library'))
        arena = rospy.get_param('~arena')
        work = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_robustness_'))
        os.makedirs(library, exist_ok=True)
        bags = {}
        for seed in (1, 2):
            bags[seed] = os.path.join(work, 'seed%d.bag' % seed)
            subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'arena:=' + arena, 'n_robots:=8',
                            'ticks:=%d' % TICKS, 'seed:=%d' % seed, 'bag:=' + bags[seed]], check=True, timeout=120,
                           stdout=subprocess.DEVNULL)
        shutil.copy(bags[1], os.path.join(library, 'reference.bag'))
        subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'arena:=' + arena, 'n_robots:=8',
                        'ticks:=%d' % TICKS, 'seed:=1', 'noise/all/level:=0.02',
                        'bag:=' + os.path.join(library, 'real_noise.bag')], check=True, timeout=120,
                       stdout=subprocess.DEVNULL)
        made = {'noise': NOISE, 'pd1': PD1, 'pd2': PD2, 'unstable': UNSTABLE, 'death': DEATH}
        for name, words in made.items():
            with_words(bags[2], os.path.join(library, name + '.bag'), words, seed=1)

        reference = read_run(os.path.join(library, 'reference.bag'), INTERVAL, ticks=False)
        other = read_run(os.path.join(library, 'noise.bag'), INTERVAL, ticks=False)
        P0 = [s.P for s in reference.samples]
        P1 = [s.P for s in other.samples]
        self.assertEqual(len(P0), TICKS // INTERVAL)
        self.assertNotEqual(P0, P1, 'the two seeds should deliver differently')
        # The Python mirror reads the words as the core does.
        words = robustness_words(other.run_info.world_constants)
        self.assertEqual(words['noise'], NOISE)
        self.assertEqual(words['noise_level'], 0.02)
        self.assertEqual(words['without_noise'], reference.run_info.world_constants)

        tables = {}
        for defs in ('paper', 'authors_code', 'authors_code_2020'):
            out = os.path.join(work, defs)
            subprocess.run(['rosrun', 'swarm_forage', 'run_tables', library, 'out:=' + out,
                            'sample_interval:=%d' % INTERVAL, 'definitions:=' + defs], check=True, timeout=120,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            tables[defs] = {(r['measure'], float(r['death']), r['noise']): r for r in rows(out, 'robustness.csv')}
            self.assertEqual(len(tables[defs]), 6, tables[defs].keys())
            self.assertEqual(len(rows(out, 'robustness_runs.csv')), 6)
        paper, authors, sierra = tables['paper'], tables['authors_code'], tables['authors_code_2020']

        saa = paper[('saa', 0.0, NOISE)]
        d = dtw(P1, P0, lambda i, j: abs(P1[i] - P0[j]))
        self.assertEqual((saa['valid'], saa['status']), ('1', 'ok'))
        self.assertEqual(float(saa['value']), d)
        self.assertAlmostEqual(float(saa['normalized']), sigma(-d) - sigma(d), places=12)
        self.assertEqual(float(saa['noise_level']), 0.02)
        self.assertEqual((float(saa['P']), float(saa['P_reference'])), (P1[-1], P0[-1]))
        # The authors' curve: blocks per tick so far (cosm's cum_avg_transported). authors_code warps it by
        # sample row (their collated tables' index), authors_code_2020 by tick (their "clock" column).
        t = [INTERVAL * (k + 1) for k in range(len(P0))]
        a1, a0 = [p / t[k] for k, p in enumerate(P1)], [p / t[k] for k, p in enumerate(P0)]
        d_authors = dtw(a1, a0, lambda i, j: abs(i - j) + abs(a1[i] - a0[j]))
        self.assertAlmostEqual(float(authors[('saa', 0.0, NOISE)]['value']), d_authors, places=14)
        self.assertGreater(d_authors, 0.0)
        d_sierra = dtw(a1, a0, lambda i, j: abs(t[i] - t[j]) + abs(a1[i] - a0[j]))
        self.assertAlmostEqual(float(sierra[('saa', 0.0, NOISE)]['value']), d_sierra, places=14)

        # The real noisy run: its world's words, its noise-free reference the same seed without them.
        real = read_run(os.path.join(library, 'real_noise.bag'), INTERVAL, ticks=False)
        real_words = robustness_words(real.run_info.world_constants)
        self.assertEqual(real_words['without_noise'], reference.run_info.world_constants)
        self.assertEqual(sorted(real_words['devices']),
                         ['ground', 'heading', 'light', 'position', 'proximity', 'wheels'])
        P2 = [s.P for s in real.samples]
        row = paper[('saa', 0.0, real_words['noise'])]
        self.assertEqual((row['valid'], row['reference']), ('1', saa['reference']))
        self.assertEqual(float(row['noise_level']), 0.02)
        self.assertEqual(float(row['value']), dtw(P2, P0, lambda i, j: abs(P2[i] - P0[j])))

        # paper: theta = P - (T - T_bar)/T P_reference, the reference the run without population dynamics.
        pd1 = paper[('pd', 0.0001, '')]
        t_bar, why = queue_time(robustness_words(PD1), 'paper')
        self.assertEqual(why, '')
        self.assertAlmostEqual(float(pd1['T_bar']), t_bar, places=9)
        self.assertEqual(float(pd1['T']), TICKS)
        theta = P1[-1] - (TICKS - t_bar) / TICKS * P0[-1]
        self.assertAlmostEqual(float(pd1['value']), theta, places=9)
        self.assertAlmostEqual(float(pd1['normalized']), sigma(theta) - sigma(-theta), places=12)
        self.assertEqual(pd1['reference'], saa['reference'])  # both: the reference run's identity
        # authors_code: reference = the lowest rates (PD1): theta(PD1) = 0; PD2 has twice the rates, W0/W = 2;
        # on the last row of their curve, blocks per tick.
        self.assertEqual(float(authors[('pd', 0.0001, '')]['value']), 0.0)
        self.assertAlmostEqual(float(authors[('pd', 0.0002, '')]['value']), (P1[-1] - 2 * P1[-1]) / TICKS, places=12)
        self.assertEqual(authors[('pd', 0.0002, '')]['reference'], pd1['identity'])
        # An unstable queue: no number, the reason instead; death only too under paper (its own reference
        # under authors_code: theta 0).
        for table in (paper, authors):
            unstable = table[('pd', 0.0, '')]
            self.assertEqual((unstable['valid'], float(unstable['value'])), ('0', 0.0))
            self.assertIn('no steady state', unstable['status'])
        self.assertIn('no steady state', paper[('pd', 0.0003, '')]['status'])
        self.assertEqual((authors[('pd', 0.0003, '')]['valid'], float(authors[('pd', 0.0003, '')]['value'])), ('1', 0.0))
        # authors_code_2020, sierra's calc_tasked_swarm_time against the run without population dynamics: a stable
        # queue is the paper's; death only theta = P(N); lambda 0.003 > mu 0.002 gives T_bar = 1/(mu - lambda) -
        # 1/mu = -1000 - 500 and theta = P - (T + 1500)/T P_ideal.
        self.assertAlmostEqual(float(sierra[('pd', 0.0001, '')]['value']), theta, places=9)
        death = sierra[('pd', 0.0003, '')]
        self.assertEqual((death['valid'], float(death['value']), float(death['T_bar'])), ('1', P1[-1], TICKS))
        unstable = sierra[('pd', 0.0, '')]
        self.assertEqual(unstable['valid'], '1', unstable)
        self.assertAlmostEqual(float(unstable['T_bar']), -1500.0, places=6)
        self.assertAlmostEqual(float(unstable['value']), P1[-1] - (TICKS + 1500.0) / TICKS * P0[-1], places=6)
        self.assertEqual(unstable['reference'], saa['reference'])
        # The queue's prediction beside every PD row; these hand-made bags hold no world/population, so nothing
        # is measured. PD1: lambda 0.0011, mu 0.0025: W = 1/0.0014 ticks, L = 0.0011/0.0014 robots.
        self.assertAlmostEqual(float(pd1['time_out_queue']), 1 / 0.0014, places=9)
        self.assertAlmostEqual(float(pd1['out_queue']), 0.0011 / 0.0014, places=12)
        self.assertEqual((pd1['time_out_measured'], pd1['out_measured'], pd1['outages'], pd1['queue_differs']),
                         ('', '', '', ''))
        self.assertEqual(paper[('pd', 0.0, '')]['time_out_queue'], '')  # no steady state, no prediction

        # Live: `rosbag play` of two of the bags into the .test's metrics_node (the same library).
        finals = {}
        rospy.Subscriber('/metrics/robustness', Robustness,
                         lambda m: finals.__setitem__(m.death, m) if m.final else None, queue_size=1000)
        topics = ['/world/run_info', '/world/performance', '/swarm/status']
        for name in ('noise', 'pd2'):
            subprocess.run(['rosbag', 'play', '--clock', '--quiet', '-r', '100', '--queue=100000',
                            '--wait-for-subscribers', os.path.join(library, name + '.bag'), '--topics'] + topics,
                           check=True, timeout=120)
        deadline = time.time() + 300
        while len(finals) < 2 and time.time() < deadline:
            time.sleep(0.1)
        self.assertEqual(sorted(finals), [0.0, 0.0002])
        live_saa, live_pd = finals[0.0], finals[0.0002]
        self.assertEqual(live_saa.saa_distance, float(saa['value']))
        self.assertTrue(live_saa.saa_valid, live_saa.saa_status)
        self.assertEqual(live_saa.noise, NOISE)
        self.assertFalse(live_saa.pd_valid)
        pd2 = paper[('pd', 0.0002, '')]
        self.assertEqual(live_pd.theta, float(pd2['value']))
        self.assertEqual(live_pd.T_bar, float(pd2['T_bar']))
        self.assertTrue(live_pd.pd_valid, live_pd.pd_status)
        self.assertAlmostEqual(live_pd.arrival_rate, 0.0022, places=15)


if __name__ == '__main__':
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    rostest.rosrun('swarm_forage', 'robustness_metrics', TestRobustnessMetrics)
