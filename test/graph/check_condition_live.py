#!/usr/bin/env python3
"""dynamic_reconfigure of the condition's target and of a measured series on a realtime run: target
carry_speed -> speed, then a malformed series file (refused naming its line, nothing changes), then a
good one: the published and recorded throttle carry the target, the file and its digest, and V follows
the file's interpolation from the switch on."""
import os
import sys
import tempfile
import unittest

import dynamic_reconfigure.client
import numpy
import rospy
import rostest
from swarm_forage.msg import RunEnd, Throttle

from check_condition_series import fnv64  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import LiveThrottle, open_bag, removed_at_exit, write  # noqa: E402

PROFILE = 't,V\n200,0.2\n400,-0.3\n580,0.5\n'


class TestConditionLive(LiveThrottle, unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_condition_live')
        removed_at_exit(os.path.dirname(rospy.get_param('~bag')))
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_live_'))
        cls.throttle, cls.end = [], []
        rospy.Subscriber('environment/throttle', Throttle, cls.throttle.append, queue_size=1000)
        rospy.Subscriber('world/run_end', RunEnd, cls.end.append, queue_size=1)

    def test_target_and_series_live(self):
        t = self.throttle_after(10)
        self.assertEqual((t.waveform, t.value, t.target), ('constant', 0.4, 'carry_speed'))
        env = dynamic_reconfigure.client.Client('/environment', timeout=30)
        cfg = env.update_configuration({'target': 'speed'})
        self.assertEqual(cfg['last_change'], 'applied')
        t = self.throttle_after(self.throttle[-1].tick + 3)
        self.assertEqual((t.waveform, t.value, t.target), ('constant', 0.4, 'speed'))

        bad = write(self.tmp, 'bad.csv', 't,V\n0,0\n10,1.5\n')
        cfg = env.update_configuration({'waveform': 'series', 'series': bad})
        self.assertTrue(cfg['last_change'].startswith('refused: '), cfg['last_change'])
        self.assertIn("series file '%s' line 3: V 1.5 is not within [-1, 1]" % bad, cfg['last_change'])
        self.assertEqual((cfg['waveform'], cfg['target']), ('constant', 'speed'))
        t = self.throttle_after(self.throttle[-1].tick + 3)
        self.assertEqual((t.waveform, t.value, t.target), ('constant', 0.4, 'speed'))

        good = write(self.tmp, 'profile.csv', PROFILE)
        cfg = env.update_configuration({'waveform': 'series', 'series': good, 'target': 'manipulation_time'})
        self.assertEqual(cfg['last_change'], 'applied')
        switched = self.throttle_after(self.throttle[-1].tick + 3).tick

        self.wait_for('world/run_end', lambda: self.end, timeout=240)
        self.assertEqual(self.end[-1].reason, '')
        with open_bag(self.end[-1].bag) as bag:
            recorded = [m for _, m, _ in bag.read_messages(topics=['/environment/throttle'])]
            applied = {m.tick: m.throttle for _, m, _ in bag.read_messages(topics=['/world/performance'])}
        series = [m for m in recorded if m.waveform == 'series']
        self.assertTrue(series and series[0].tick <= switched, [(m.tick, m.waveform) for m in recorded])
        digest = fnv64(PROFILE.encode())
        for m in series:
            self.assertEqual((m.target, m.series, m.series_digest), ('manipulation_time', good, digest))
        # Each recorded throttle is V of its own tick (realtime: the world applies the latest one it has).
        rows = numpy.array([[200, 0.2], [400, -0.3], [580, 0.5]])
        self.assertGreater(len(series), 500)
        for m in series:
            self.assertAlmostEqual(m.value, numpy.interp(m.tick / 5.0, rows[:, 0], rows[:, 1]), delta=1e-12)
        self.assertEqual(applied[max(applied)], 0.5)  # after the last row its V holds
        print('series from tick %d; %d recorded throttles follow the file' % (series[0].tick, len(series)))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'condition_live', TestConditionLive)
