#!/usr/bin/env python3
"""Measured conditions and condition targets with real nodes and bags (docs/nodes-and-parameters.md,
environment_node): a series run records, at every tick, the file's linearly interpolated V (held before
the first and after the last row), its target, file and digest, the same in the node graph and headless;
the identity follows the file's content, not its path; malformed files are refused before tick 0 naming
the file and the line (run_experiment, environment_node, experiment files); each target changes what it
should and nothing else."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy
import rostest

from check_headless_identity import messages  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import open_bag, removed_at_exit, write  # noqa: E402

PACKAGE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
from swarm_forage.experiment import ExperimentError  # noqa: E402
from swarm_forage.experiment import file as experiment_file  # noqa: E402

TPS = 5.0
# Rows from 5 s to 45 s in a 60 s run: the first V holds before 5 s, the last after 45 s.
PROFILE = 't,V\n# measured\n5,0.1\n20,0.6\n31.3,-0.2\n45,0.35\n'
BAD = [('t,V\n0,0\n10,1.5\n', 3, 'not within [-1, 1]'),
       ('0,0\n0,0.1\n', 2, 'does not increase'),
       ('t,V\n0,zero\n', 2, 'is not two numbers'),
       ('0,nan\n', 1, 'not finite'),
       ('t,V\n', 2, 'ends without a row'),
       ('1O,0.9\n20,0.5\n', 1, "field 1 '1O' is not a number")]  # a mistyped first row is no header


def fnv64(data):
    """The digest the core computes (ConditionSeries::digest): FNV-1a 64 of the file's bytes."""
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return '%016x' % h


def run(*words, timeout=180):
    return subprocess.run(['rosrun', 'swarm_forage'] + list(words), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=timeout)


def read(path, *topics):
    with open_bag(path) as bag:
        return [(t, m) for t, m, _ in bag.read_messages(topics=list(topics))]


class ConditionSeries(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_series_'))
        cls.profile = write(cls.tmp, 'profile.csv', PROFILE)

    def headless(self, bag, *words):
        proc = run('run_experiment', 'bag:=' + bag, *words)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        return read(bag, '/world/run_info')[0][1]

    def test_graph_and_headless_record_the_interpolated_file(self):
        ticks = 300
        words = ['n_robots:=16', 'ticks:=%d' % ticks, 'seed:=3', 'waveform:=series', 'series:=' + self.profile,
                 'target:=manipulation_time']
        graph_bag, headless_bag = os.path.join(self.tmp, 'graph.bag'), os.path.join(self.tmp, 'headless.bag')
        graph = run('forage', 'metrics:=false', 'wait_for_subscribers:=0', 'record:=true', 'bag:=' + graph_bag,
                    *words)
        self.assertEqual(graph.returncode, 0, graph.stdout[-3000:])
        self.headless(headless_bag, *words)
        a, b = messages(graph_bag), messages(headless_bag)
        for topic in sorted(a):
            if topic not in ('/world/provenance', '/world/run_end'):
                self.assertEqual(a[topic], b[topic], '%s differs between the graph and headless' % topic)

        with open(self.profile, 'rb') as f:
            digest = fnv64(f.read())
        rows = numpy.loadtxt(self.profile, delimiter=',', skiprows=2)
        applied = [m for _, m in read(graph_bag, '/world/performance')]
        self.assertEqual([m.tick for m in applied], list(range(ticks)))
        for m in applied:  # numpy.interp holds the end values, as the docs say a series does
            want = numpy.interp(m.tick / TPS, rows[:, 0], rows[:, 1])
            self.assertAlmostEqual(m.throttle, want, delta=1e-12, msg='tick %d' % m.tick)
        self.assertEqual(applied[0].throttle, 0.1)
        self.assertEqual(applied[-1].throttle, 0.35)
        recorded = [m for _, m in read(graph_bag, '/environment/throttle')]
        self.assertGreater(len(recorded), 100)  # at tick 0 and whenever V changes
        info = read(graph_bag, '/world/run_info')[0][1]
        for t in recorded + [info.environment]:
            self.assertEqual((t.waveform, t.target, t.series, t.series_digest),
                             ('series', 'manipulation_time', self.profile, digest))
        print('%d ticks follow the file; digest %s, identity %s' % (ticks, digest, info.identity))

    def test_identity_follows_the_content_not_the_path(self):
        elsewhere = os.path.join(self.tmp, 'copy')
        os.makedirs(elsewhere)
        same = shutil.copy(self.profile, os.path.join(elsewhere, 'renamed.csv'))
        changed = write(self.tmp, 'changed.csv', PROFILE.replace('0.35', '0.36'))
        ids = {}
        for name, path in (('profile', self.profile), ('same', same), ('changed', changed)):
            folder = os.path.join(self.tmp, 'id_' + name)
            proc = run('run_experiment', 'bag_dir:=' + folder, 'n_robots:=2', 'ticks:=20', 'waveform:=series',
                       'series:=' + path)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            bags = os.listdir(folder)
            self.assertEqual(len(bags), 1, bags)
            ids[name] = read(os.path.join(folder, bags[0]), '/world/run_info')[0][1].identity
            with open(path, 'rb') as f:
                tag = 'series-' + fnv64(f.read())[:8]
            self.assertTrue(bags[0].endswith('_%s_seed0_%s.bag' % (tag, ids[name])), bags)
        self.assertEqual(ids['profile'], ids['same'], 'the same content under another path')
        self.assertNotEqual(ids['profile'], ids['changed'], 'a changed file')
        print('identities: %s' % ids)

    def test_malformed_files_are_refused_before_tick_0_with_the_line(self):
        for k, (text, line, why) in enumerate(BAD):
            path = write(self.tmp, 'bad%d.csv' % k, text)
            expected = "series file '%s' line %d" % (path, line)
            folder = os.path.join(self.tmp, 'bad%d' % k)
            proc = run('run_experiment', 'bag_dir:=' + folder, 'n_robots:=2', 'ticks:=20', 'waveform:=series',
                       'series:=' + path)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(expected, proc.stdout)
            self.assertIn(why, proc.stdout)
            self.assertFalse(os.path.exists(folder) and os.listdir(folder), 'a refused run left a record')
            # The experiment file is checked by the same rule (run_experiment --conditions).
            exp = write(self.tmp, 'exp%d.yaml' % k, 'name: bad\narena: 32x16\ncontrollers: [crw]\nsizes: [2]\n'
                        'runs: 1\nticks: 20\nconditions:\n  - {waveform: series, series: bad%d.csv}\n' % k)
            with self.assertRaises(ExperimentError) as err:
                experiment_file.load(exp)
            self.assertIn(expected, str(err.exception))
        # environment_node refuses it at start-up (exit 2), before any tick.
        path = os.path.join(self.tmp, 'bad0.csv')
        proc = run('environment_node', '__name:=bad_environment', '_waveform:=series', '_series:=' + path,
                   timeout=60)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn("series file '%s' line 3" % path, proc.stdout)
        print('refused: %s' % proc.stdout.strip().splitlines()[-1])

    def test_experiment_file_takes_series_relative_to_it_and_targets(self):
        exp = experiment_file.load(os.path.join(PACKAGE, 'config', 'experiments', 'measured_32x16.yaml'))
        labels = [c['label'] for c in exp['conditions']]
        with open(os.path.join(PACKAGE, 'config', 'conditions', 'example_profile.csv'), 'rb') as f:
            short = fnv64(f.read())[:8]
        self.assertEqual(labels, ['null', 'series-' + short, 'series-%s-manipulation_time' % short,
                                  'constant0.3-speed'])
        bad = write(self.tmp, 'extra.yaml', 'name: x\narena: 32x16\ncontrollers: [crw]\nsizes: [2]\nruns: 1\n'
                    'ticks: 20\nconditions:\n  - {waveform: series, series: profile.csv, beta: 0.4}\n')
        with self.assertRaises(ExperimentError) as err:
            experiment_file.load(bad)
        self.assertIn('waveform series takes no beta', str(err.exception))

    def snapshots(self, name, *condition):
        bag = os.path.join(self.tmp, 'target_%s.bag' % name)
        # The corrected model's pick-up: fordyca_2019's block penalties time it by their own rule (FIDELITY.md (7)).
        self.headless(bag, 'n_robots:=16', 'ticks:=400', 'seed:=5', 'record_every:=1', 'model:=swarm_forage',
                      *condition)
        return [m for _, m in read(bag, '/world/robots')]

    def test_each_target_changes_what_it_should_and_nothing_else(self):
        half = ('waveform:=constant', 'beta:=0.5')
        none = self.snapshots('none')
        carry = self.snapshots('carry', *half)
        speed = self.snapshots('speed', *half, 'target:=speed')
        manip = self.snapshots('manip', *half, 'target:=manipulation_time')
        pose = lambda m: (list(m.x), list(m.y), list(m.theta))  # noqa: E731
        first = next(k for k, m in enumerate(none) if max(m.carried_block) >= 0)  # the first pick-up shows
        self.assertGreater(first, 1)
        # carry_speed and manipulation_time move robots that carry nothing exactly as without a condition.
        for k in range(first + 1):
            self.assertEqual(pose(carry[k]), pose(none[k]), 'carry_speed, tick %d' % k)
            self.assertEqual(pose(manip[k]), pose(none[k]), 'manipulation_time, tick %d' % k)
        # speed: every robot at half speed from the first tick.
        for i in range(16):
            d0 = numpy.hypot(none[1].x[i] - none[0].x[i], none[1].y[i] - none[0].y[i])
            d1 = numpy.hypot(speed[1].x[i] - speed[0].x[i], speed[1].y[i] - speed[0].y[i])
            self.assertAlmostEqual(d1, 0.5 * d0, delta=1e-5)
        self.assertNotEqual(pose(speed[first]), pose(none[first]))
        # manipulation_time: the first pick-up finishes 0.5 x 10 s = 25 ticks later, by the same robot.
        robot = max(range(16), key=lambda i: none[first].carried_block[i])
        later = next(k for k, m in enumerate(manip) if max(m.carried_block) >= 0)
        self.assertEqual(later, first + int(0.5 * 10 * TPS))
        self.assertGreaterEqual(manip[later].carried_block[robot], 0)
        print('first pick-up at tick %d; with manipulation_time V 0.5 at tick %d' % (first, later))

    def test_bags_recorded_before_targets_stay_readable(self):
        """test/legacy_step_down.bag: the first 1,000 ticks of rosbags/crw_32x16_n16_step_down0.4.bag as recorded
        before Throttle had its target and series (rosbag filter of the old reference bag)."""
        from swarm_forage.msg import LegacyThrottle, Throttle
        legacy = os.path.join(PACKAGE, 'test', 'fixtures', 'legacy_step_down.bag')
        with open_bag(legacy) as bag:
            md5 = {c.topic: c.md5sum for c in bag._get_connections()}
        self.assertEqual(md5['/environment/throttle'], LegacyThrottle._md5sum)
        self.assertNotEqual(md5['/environment/throttle'], Throttle._md5sum)
        old = run('read_run', legacy, 'ticks:=true')
        self.assertEqual(old.returncode, 0, old.stdout)
        self.assertGreater(len(old.stdout.splitlines()), 1000)
        # rosbag fix with the package's rule gives the current definitions and the same run.
        fixed = os.path.join(self.tmp, 'fixed.bag')
        rule = os.path.join(PACKAGE, 'config', 'rosbag_migration.bmr')
        proc = subprocess.run(['rosbag', 'fix', legacy, fixed, rule],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertEqual(run('read_run', fixed, 'ticks:=true').stdout, old.stdout)
        throttles = [m for _, m in read(fixed, '/environment/throttle')]
        self.assertEqual([(m.waveform, m.target, m.series_digest) for m in throttles],
                         [('step_down', 'carry_speed', '')] * 3)
        # The identity the old run recorded is the one the current code gives the same run.
        now = read(os.path.join(PACKAGE, 'rosbags', 'swarm_forage', 'crw_32x16_n16_step_down0.4.bag'),
                   '/world/run_info')[0][1]
        self.assertEqual(read(legacy, '/world/run_info')[0][1].identity, now.identity)
        summary = subprocess.run([sys.executable, os.path.join(PACKAGE, 'scripts', 'summarize_run.py'), legacy],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
        self.assertEqual(summary.returncode, 0, summary.stdout)
        self.assertIn('step_down (beta 0.4, alpha 1000 s) on carry_speed', summary.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'condition_series', ConditionSeries)
