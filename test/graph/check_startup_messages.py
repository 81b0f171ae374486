#!/usr/bin/env python3
"""Start-up refusals and messages that say what is wrong: a bag:= without .bag whose record exists is refused
before the run; a directory given for resume:= or series:= is named as one; a node sending arrays of the wrong
length is named with that reason; the calibration's failure carries the run's own reason; forage takes a
launch file of your own by its path, ends a graph without a red "REQUIRED process ... has died!", and leaves
no temporary file whether the run ends, is killed or interrupted."""
import hashlib
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest
from swarm_forage.sweep import estimate
from swarm_forage.msg import CommandBatch, Performance, SensorBatch, SwarmStatus

TINY = ['n_robots:=4', 'ticks:=50', 'metrics:=false', 'wait_for_subscribers:=0']
RED = 'REQUIRED process'


def run(*words, env=None, timeout=300):
    return subprocess.run(['rosrun', 'swarm_forage'] + list(words), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout, env=env)


def digest(path):
    with open(path, 'rb') as f:
        return hashlib.sha1(f.read()).hexdigest()


class StartupMessages(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_startup_messages', anonymous=True)

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_startup_')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def path(self, *names):
        return os.path.join(self.tmp, *names)

    def test_bag_without_its_extension_is_refused_before_the_run(self):
        stem = self.path('foo')
        r = run('run_experiment', 'bag:=' + stem, 'n_robots:=2', 'ticks:=20')
        self.assertEqual(r.returncode, 0, r.stdout)
        self.assertEqual(os.listdir(self.tmp), ['foo.bag'])
        before = digest(stem + '.bag')
        words = "~bag '%s' is recorded as %s.bag, which exists: give a new path, or ~overwrite true" % (stem, stem)
        r = run('run_experiment', 'bag:=' + stem, 'n_robots:=2', 'ticks:=20', 'seed:=2')
        self.assertEqual(r.returncode, 2, r.stdout)  # a parameter refused at start-up, not a run that failed
        self.assertIn(words, r.stdout)
        r = run('forage', *(TINY + ['record:=true', 'bag:=' + stem, 'seed:=3']))
        self.assertEqual(r.returncode, 2, r.stdout[-3000:])
        self.assertIn(words, r.stdout)
        self.assertNotIn('world: run 0:', r.stdout, 'the run started before it was refused')
        self.assertEqual(digest(stem + '.bag'), before)
        r = run('run_experiment', 'bag:=' + stem, 'n_robots:=2', 'ticks:=20', 'seed:=4', 'overwrite:=true')
        self.assertEqual(r.returncode, 0, r.stdout)
        self.assertNotEqual(digest(stem + '.bag'), before)
        self.assertEqual(os.listdir(self.tmp), ['foo.bag'])

    def test_a_directory_for_a_file_is_named(self):
        folder = self.path('folder')
        os.mkdir(folder)
        for words, message in ((['resume:=' + folder], "~resume '%s' is a directory; valid: a checkpoint file" % folder),
                               (['checkpoint_every:=10', 'checkpoint:=' + folder],
                                "~checkpoint '%s' is a directory" % folder),
                               (['save_at:=10', 'save:=' + folder], "~save '%s' is a directory" % folder),
                               (['waveform:=series', 'series:=' + folder],
                                "~series file '%s' is a directory; valid: a CSV file" % folder)):
            r = run('run_experiment', 'n_robots:=2', 'ticks:=20', *words)
            self.assertEqual(r.returncode, 2, r.stdout)
            self.assertIn(message, r.stdout)
            self.assertNotIn('basic_filebuf', r.stdout)
        r = run('environment_node', '__name:=dir_environment', '_waveform:=series', '_series:=' + folder, timeout=60)
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn("~series file '%s' is a directory" % folder, r.stdout)

    def test_arrays_of_the_wrong_length_are_named(self):
        status = rospy.Publisher('swarm/status', SwarmStatus, queue_size=10)
        commands = rospy.Publisher('swarm/commands', CommandBatch, queue_size=10)

        def answer(m):  # a controller whose right wheel array is one short
            s = SwarmStatus(tick=m.tick, run=m.run, first_id=0, count=m.swarm_size, swarm_size=m.swarm_size,
                            controller='short_arrays')
            s.header.stamp = m.header.stamp
            status.publish(s)
            c = CommandBatch(tick=m.tick, run=m.run, first_id=0, left=[0.0] * m.swarm_size,
                             right=[0.0] * (m.swarm_size - 1), request=bytes(m.swarm_size))
            c.header.stamp = m.header.stamp
            commands.publish(c)

        sensors = rospy.Subscriber('world/sensors', SensorBatch, answer, queue_size=10)
        try:
            r = run('forage', *(TINY + ['controller:=short_arrays', 'external_controller:=short_arrays']))
        finally:
            sensors.unregister()
            status.unregister()
            commands.unregister()
        self.assertEqual(r.returncode, 1, r.stdout[-3000:])
        self.assertIn('run 0 stopped at tick 0 of 50 (tick 0: malformed swarm/commands from %s (first_id 0): left '
                      'has 4 entries, right 3, request 4, task 0' % rospy.get_name(), r.stdout)
        self.assertNotIn('no node has answered at all', r.stdout)

    def test_the_calibration_says_why_its_run_failed(self):
        with self.assertRaises(estimate.CalibrationFailed) as err:
            estimate.calibrate([{'controller': 'crw', 'n': 4, 'args': ['controller:=crw',
                                                                             'noise/light/level:=20']}], 100, 1)
        self.assertIn('the calibration run failed (exit 2)', str(err.exception))
        self.assertIn('~noise/light/level must be in [0, 10] (got 20)', str(err.exception))

    def test_forage_runs_your_own_launch_file(self):
        mine = self.path('my_graph.launch')
        with open(mine, 'w') as f:
            f.write('<launch>\n  <include file="$(find swarm_forage)/launch/foraging.launch" pass_all_args="true"/>\n'
                    '</launch>\n')
        r = run('forage', '--launch', mine, 'n_robots:=4', 'ticks:=50')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertIn('forage: run 0 complete: 50 of 50 ticks', r.stdout)
        # The metrics node's end after the final sample ends the launch as Ctrl-C would: no red death notice.
        self.assertNotIn(RED, r.stdout)
        r = run('forage', '--launch', mine, 'n_robots:=4', 'ticks:=50', 'nodelet:=true')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertNotIn(RED, r.stdout)
        r = run('forage', '--launch', mine, 'n_robot:=4')
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn('%s declares no argument n_robot' % mine, r.stdout)
        alone = self.path('alone.launch')
        with open(alone, 'w') as f:
            f.write('<launch>\n  <arg name="n_robots" default="4"/>\n</launch>\n')
        r = run('forage', '--launch', alone)
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn('declares no argument outcome: include foraging.launch with pass_all_args="true"', r.stdout)
        r = run('forage', '--launch', self.path('missing.launch'))
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn('launch file %s does not exist' % self.path('missing.launch'), r.stdout)

    def test_forage_leaves_no_temporary_file(self):
        tmpdir = self.path('tmpdir')
        os.mkdir(tmpdir)
        env = dict(os.environ, TMPDIR=tmpdir)
        r = run('forage', *TINY, env=env)
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertEqual(os.listdir(tmpdir), [])
        for sig, words in ((signal.SIGTERM, 'terminated (SIGTERM)'), (signal.SIGINT, 'interrupted (Ctrl-C)'),
                           (signal.SIGHUP, 'terminated (SIGHUP)')):
            proc = subprocess.Popen(['rosrun', 'swarm_forage', 'forage', 'n_robots:=4', 'ticks:=100000000',
                                     'metrics:=false', 'wait_for_subscribers:=0'], stdout=subprocess.PIPE,
                                    stderr=subprocess.STDOUT, text=True, env=env)
            try:  # the run is under way (its outcome file exists)
                rospy.wait_for_message('/world/performance', Performance, timeout=300)
            finally:
                self.assertTrue(os.listdir(tmpdir), 'no outcome file while the run goes on')
                proc.send_signal(sig)
                out = proc.communicate(timeout=120)[0]
            self.assertEqual(proc.returncode, 1, out[-3000:])
            self.assertIn('forage: ' + words, out)
            self.assertIn('run 0 stopped at tick', out)
            self.assertEqual(os.listdir(tmpdir), [], '%s left %s' % (words, os.listdir(tmpdir)))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_startup_messages', StartupMessages, sys.argv)
