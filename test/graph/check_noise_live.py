#!/usr/bin/env python3
"""The noise changed by hand in a realtime run (world_node's ~noise dynamic_reconfigure): the knob starts
with the start-up noise; a change is applied from the next tick, published and recorded on world/noise;
a bad level is refused with the reason and changes nothing; the bag, changed by hand, is refused as a
run-library reference."""
import os
import sys
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from swarm_forage.msg import NoiseChange, Performance, RunEnd
from swarm_forage.srv import Compute

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import LiveThrottle, open_bag, removed_at_exit  # noqa: E402


class TestNoiseLive(LiveThrottle, unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_noise_live')
        removed_at_exit(os.path.dirname(rospy.get_param('~bag')))
        cls.performance, cls.noise, cls.end = [], [], []
        rospy.Subscriber('world/performance', Performance, cls.performance.append, queue_size=1000)
        rospy.Subscriber('world/noise', NoiseChange, cls.noise.append, queue_size=10)
        rospy.Subscriber('world/run_end', RunEnd, cls.end.append, queue_size=1)

    def test_live_change(self):
        self.wait_for('tick 10', lambda: self.performance and self.performance[-1].tick >= 10)
        knob = dynamic_reconfigure.client.Client('/world/noise', timeout=30)
        cfg = knob.get_configuration(timeout=10)
        self.assertEqual((cfg['light_level'], cfg['light_model'], cfg['wheels_level'], cfg['last_change']),
                         (0.01, 'gaussian', 0.0, 'start-up parameters'))
        self.assertEqual(self.noise, [])  # nothing changed yet: nothing published

        asked_at = self.performance[-1].tick
        cfg = knob.update_configuration({'wheels_level': 0.05, 'wheels_model': 'uniform'})
        self.assertEqual(cfg['last_change'], 'applied')
        self.wait_for('world/noise', lambda: self.noise)
        change = self.noise[-1]
        self.assertEqual(change.noise, 'noise/light=gaussian:0.01 noise/wheels=uniform:0.05')
        self.assertGreater(change.tick, asked_at)

        cfg = knob.update_configuration({'ground_level': 1.5})
        self.assertIn('noise/ground/level must be a probability in [0, 1] (got 1.5)', cfg['last_change'])
        self.assertEqual(cfg['ground_level'], 0.0)
        cfg = knob.update_configuration({'heading_model': 'cauchy', 'heading_level': 0.1})
        self.assertIn("~noise/heading_model 'cauchy' is not valid; valid: gaussian, uniform", cfg['last_change'])
        self.assertEqual(cfg['heading_level'], 0.0)
        self.assertEqual(len(self.noise), 1)  # refused changes publish nothing

        self.wait_for('world/run_end', lambda: self.end, timeout=180)
        self.assertEqual(self.end[-1].reason, '')
        with open_bag(self.end[-1].bag) as bag:
            recorded = [m for _, m, _ in bag.read_messages(topics=['/world/noise'])]
            info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
        self.assertEqual([(m.run, m.tick, m.noise) for m in recorded], [(change.run, change.tick, change.noise)])
        self.assertTrue(info.world_constants.split(' quirks=')[0].endswith(' noise/light=gaussian:0.01'),
                        info.world_constants)

        rospy.wait_for_service('metrics/compute', 30)
        folder = os.path.dirname(self.end[-1].bag)
        res = rospy.ServiceProxy('metrics/compute', Compute)(directory=folder, output=folder)
        expected = 'the noise was changed live at tick %d (to %s)' % (change.tick, change.noise)
        self.assertTrue(any(expected in p for p in res.problems), res.problems)
        print('noise changed at tick %d; %s' % (change.tick, res.problems[0]))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'noise_live', TestNoiseLive, sys.argv)
