#!/usr/bin/env python3
"""With ~exit_on_final, metrics_node flushes before it exits: over 10 consecutive runs, a subscriber
receives every run's final scalability, self_organization, reactivity, adaptability and performance
message. e(t) carries a validity flag per sample."""
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from swarm_forage.msg import (FlexibilityMetric, IntervalPerformance, Performance, ScalabilityMetric,
                              SelfOrganizationMetric)

RUNS = 10
TICKS = 1000
TOPICS = [('scalability', ScalabilityMetric), ('self_organization', SelfOrganizationMetric),
          ('reactivity', FlexibilityMetric), ('adaptability', FlexibilityMetric),
          ('performance', IntervalPerformance)]


class TestFinalMetrics(unittest.TestCase):
    def test_every_final_message_arrives(self):
        rospy.init_node('check_final_metrics')
        arena = rospy.get_param('~arena')
        finals = {topic: [] for topic, _ in TOPICS}
        for topic, kind in TOPICS:
            rospy.Subscriber('/metrics/' + topic, kind,
                             lambda m, t=topic: finals[t].append(m) if m.final else None, queue_size=1000)
        rospy.Subscriber('/world/performance', Performance, lambda m: None, queue_size=100000)
        for run in range(RUNS):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'forage', 'arena:=' + arena, 'n_robots:=4',
                                   'ticks:=%d' % TICKS, 'seed:=%d' % (run + 1), 'sample_interval:=250',
                                   'waveform:=step_down', 'beta:=0.4', 'wait_for_subscribers:=2'],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            deadline = time.time() + 120  # delivery is asynchronous; the node has exited by now
            while time.time() < deadline and any(len(f) < run + 1 for f in finals.values()):
                time.sleep(0.05)
            self.assertEqual({t: len(f) for t, f in finals.items()}, {t: run + 1 for t in finals},
                             'run %d: final messages missing' % run)
        for m in finals['scalability']:
            self.assertEqual(len(m.e_t_valid), len(m.e_t))
            for value, valid in zip(m.e_t, m.e_t_valid):
                if not valid:
                    self.assertEqual(value, 0.0)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_final_metrics', TestFinalMetrics, sys.argv)
