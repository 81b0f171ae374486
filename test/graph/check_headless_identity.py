#!/usr/bin/env python3
"""A headless run (run_experiment, no master) records the same run as the node graph: for
each controller and under a step waveform, one seed gives bit-identical world/performance, swarm/status,
environment/throttle, snapshots and run identity in both bags."""
import io
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import open_bag, removed_at_exit

TICKS = 400
COMMON = ['n_robots:=40', 'ticks:=%d' % TICKS, 'seed:=7']
# Per topic: fields that legitimately differ (publish sequence numbers, the bag's own path).
IGNORED = {'/world/run_end': ('bag',)}


def comparable(msg, ignored=()):
    """The message's bytes with header.seq cleared (a publisher's counter, not part of the run)."""
    if hasattr(msg, 'header'):
        msg.header.seq = 0
    for field in ignored:
        setattr(msg, field, type(getattr(msg, field))())
    buf = io.BytesIO()
    msg.serialize(buf)
    return buf.getvalue()


def messages(path):
    """topic -> list of (stamp, bytes), in recorded order."""
    out = {}
    with open_bag(path) as bag:
        for topic, msg, stamp in bag.read_messages():
            out.setdefault(topic, []).append((stamp.to_nsec(), comparable(msg, IGNORED.get(topic, ()))))
    return out


class HeadlessIdentity(unittest.TestCase):
    def same_run(self, *args):
        folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_headless_'))
        graph_bag, headless_bag = os.path.join(folder, 'graph.bag'), os.path.join(folder, 'headless.bag')
        graph = subprocess.run(['rosrun', 'swarm_forage', 'forage', 'metrics:=false', 'wait_for_subscribers:=0',
                                'record:=true', 'bag:=' + graph_bag] + COMMON + list(args),
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
        self.assertEqual(graph.returncode, 0, graph.stdout[-3000:])
        headless = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'bag:=' + headless_bag] + COMMON +
                                  list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  timeout=180)
        self.assertEqual(headless.returncode, 0, headless.stdout)
        a, b = messages(graph_bag), messages(headless_bag)
        self.assertEqual(sorted(a), sorted(b), 'the two bags record different topics')
        for topic in ('/world/performance', '/swarm/status'):
            self.assertEqual(len(a[topic]), TICKS, topic)
        # The condition is recorded at tick 0 and when V changes (a step: beta, beta/2 at alpha, 0).
        self.assertEqual(len(a['/environment/throttle']), 3 if 'waveform:=step_down' in args else 1)
        for topic in sorted(a):
            self.assertEqual(len(a[topic]), len(b[topic]), topic)
            for k, (x, y) in enumerate(zip(a[topic], b[topic])):
                self.assertEqual(x, y, '%s message %d differs between the graph and run_experiment (%s)'
                                 % (topic, k, ' '.join(args)))
        print('%s: %d topics, %d messages identical' % (' '.join(args), len(a), sum(len(v) for v in a.values())))

    def test_crw(self):
        self.same_run('controller:=crw')

    def test_dpo(self):
        self.same_run('controller:=dpo')

    def test_gp_dpo(self):
        self.same_run('controller:=gp_dpo')

    def test_step_down(self):
        self.same_run('controller:=dpo', 'waveform:=step_down', 'beta:=0.4', 'alpha:=40')

    def test_the_default_model_is_fordyca_2019(self):
        """A run without `model` is a run of fordyca_2019: the same identity and the same bag; the corrected
        model is another run."""
        folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_default_model_'))
        bags = {}
        for label, words in (('plain', []), ('named', ['model:=fordyca_2019']), ('corrected', ['model:=swarm_forage'])):
            bags[label] = os.path.join(folder, label + '.bag')
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'bag:=' + bags[label],
                                   'controller:=dpo'] + COMMON + words, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=180)
            self.assertEqual(proc.returncode, 0, proc.stdout)
        plain, named, corrected = (messages(bags[k]) for k in ('plain', 'named', 'corrected'))
        self.assertEqual(plain, named, 'a run without model differs from one with model:=fordyca_2019')
        self.assertNotEqual(plain['/world/run_info'], corrected['/world/run_info'])
        with open_bag(bags['plain']) as bag:
            info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
        self.assertIn('quirks=rim_ground_sensors,block_penalties,light_occlusion', info.world_constants)

    def test_bad_words_are_refused_with_the_reason(self):
        for words, message in ((['n_robot:=3'], 'n_robot is not a run_experiment parameter; valid: arena, n_robots'),
                               (['compression:=zip'], "~compression 'zip' is not valid; valid: none, lz4, bz2"),
                               (['n_robots:=0'], '~n_robots must be in [1, 10000000]'),
                               (['64'], "'64' is not a parameter: give name:=value"),
                               (['crw/wander_forse:=3'], 'wander_forse is not a crw constant'),
                               (['waveform:=step_up', 'ticks:=100', 'alpha:=50'], '~alpha 50 s is not within the run')):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment'] + words, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(proc.returncode, 2, (words, proc.stdout))
            self.assertIn(message, proc.stdout, words)

    def test_help_lists_every_parameter_and_runs_nothing(self):
        # --help ran 50,000 ticks of the defaults, as did no argument at all.
        tmp = tempfile.mkdtemp(prefix='swarm_forage_help_')
        try:
            bag = os.path.join(tmp, 'never.bag')
            for words, code in ((['--help', 'bag:=' + bag], 0), (['-h'], 0), ([], 2)):
                proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment'] + words, stdout=subprocess.PIPE,
                                      stderr=subprocess.STDOUT, text=True, timeout=60)
                self.assertEqual(proc.returncode, code, (words, proc.stdout))
                rows = {line.split()[0]: line for line in proc.stdout.splitlines() if line.startswith('  ')}
                for name, words_in_row in (('n_robots', ['64', 'a whole number in [1, 10000000]']),
                                           ('arena', ['32x16', 'a path to an arena YAML file']),
                                           ('controller', ['crw', 'one of crw, dpo, gp_dpo']),
                                           ('beta', ['0', 'a number in [-1, 1]']),
                                           ('crw/wander_force', [])):
                    self.assertIn(name, rows, proc.stdout)
                    for w in words_in_row:
                        self.assertIn(w, rows[name])
                for name in ('ticks', 'seed', 'bag', 'bag_dir', 'outcome', 'waveform', 'alpha', 'frequency', 'phase',
                             'offset', 'record_every', 'progress', 'compression', 'threads', 'cache/min_blocks',
                             'los_radius', 'serialize_block_ops', 'ticks_per_second', 'dpo/pheromone_decay',
                             'gp_dpo/estimates'):
                    self.assertIn(name, rows, proc.stdout)
                self.assertIn('examples:', proc.stdout)
                self.assertNotIn('run_experiment: finished', proc.stdout)
            self.assertEqual(os.listdir(tmp), [])

            # run_tables: its own usage; and a folder without a usable run is a failure, not empty tables.
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', '--help'], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            for w in ('sample_interval', '1000', 'a whole number in [1, 100000000]', 'definitions',
                      'one of paper, authors_code_2019, authors_code_2020, authors_code', 'dtw_band', 'out',
                      'examples:'):
                self.assertIn(w, proc.stdout)
            with open(os.path.join(tmp, 'broken.bag'), 'w') as f:
                f.write('not a bag')
            for folder, words in ((os.path.join(tmp, 'empty'), ['no usable recorded run (no *.bag file)']),
                                  (tmp, ['broken.bag', 'no usable recorded run (1 problem, listed)'])):
                os.makedirs(os.path.join(tmp, 'empty'), exist_ok=True)
                proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', folder, 'out:=' + folder],
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
                self.assertEqual(proc.returncode, 1, proc.stdout)
                for w in words:
                    self.assertIn(w, proc.stdout)
                self.assertFalse(os.path.exists(os.path.join(folder, 'series.csv')))
        finally:
            shutil.rmtree(tmp)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'headless_identity', HeadlessIdentity)
