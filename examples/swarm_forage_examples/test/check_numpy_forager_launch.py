#!/usr/bin/env python3
"""The rospy graph as a user starts it: roslaunch swarm_forage_examples numpy_forager.launch, and
`forage --launch` with that file's path (forage's exit code and outcome line). Its normal end, the metrics
node's exit after the final sample, ends the launch as Ctrl-C would: no red "REQUIRED process [...] has died!"."""
import os
import subprocess
import sys
import unittest

import rospkg
import rostest

RED = 'REQUIRED process'
LAUNCH = os.path.join(rospkg.RosPack().get_path('swarm_forage_examples'), 'launch', 'numpy_forager.launch')


def run(cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)


class NumpyForagerLaunch(unittest.TestCase):
    def test_roslaunch_ends_quietly(self):
        r = run(['roslaunch', 'swarm_forage_examples', 'numpy_forager.launch', 'n_robots:=8', 'ticks:=100'])
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertIn('metrics: run 0 done: 8 robots, 100 ticks', r.stdout)
        self.assertNotIn(RED, r.stdout)

    def test_forage_runs_it_by_its_path(self):
        r = run(['rosrun', 'swarm_forage', 'forage', '--launch', LAUNCH, 'n_robots:=8', 'ticks:=100',
                 'controller_count:=4'])
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertIn('forage: run 0 complete: 100 of 100 ticks', r.stdout)
        self.assertNotIn(RED, r.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'numpy_forager_launch', NumpyForagerLaunch, sys.argv)
