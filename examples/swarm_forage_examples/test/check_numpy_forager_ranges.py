#!/usr/bin/env python3
"""A rospy controller that serves a wrong range is reported like any controller node: two nodes claiming
the same robots stop the run at tick 0 naming both, a range beyond the swarm is refused by the node and
reported as a gap by the world; a controller the world did not declare (~external_controller), or a
declared one nobody runs, stops the run at tick 0. Bad parameters stop the node (or world) with exit 2, and
the node leaves none of them on the master."""
import re
import sys
import unittest

import rospy
import rostest

from forager_graph import Node, controller, forager, stop_all, wait_up, world

EXTERNAL = dict(controller='numpy_forager', external_controller='numpy_forager')
MIXED = dict(controller='crw', external_controller='numpy_forager')


class TestNumpyForagerRanges(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_numpy_forager_ranges')

    def stopped(self, world_params, nodes):
        """Runs a world with `nodes` until it stops; (its stop reason, the nodes' stderr)."""
        wait_up(nodes)
        w = world(**world_params)
        try:
            code = w.wait(timeout=300)
        finally:
            stop_all([w] + nodes)
        err = w.stderr()
        self.assertEqual(code, 1, err)
        report = re.search(r'run 0 stopped at tick (\d+) of \d+ \((.*)\)', err)
        self.assertIsNotNone(report, 'world_node said nothing about the stop:\n' + err)
        return report.group(2), ''.join(n.stderr() for n in nodes)

    def test_overlap_names_both_nodes(self):
        reason, _ = self.stopped(MIXED, [controller(), forager(first_id=32)])
        self.assertIn('tick 0: robots [32, 64) on swarm/', reason)
        self.assertIn('claimed by both /controller ([0, 64)) and /numpy_forager ([32, 64))', reason)

    def test_range_beyond_the_swarm(self):
        reason, err = self.stopped(dict(EXTERNAL, step_timeout=3.0), [forager(first_id=64)])
        self.assertIn('tick 0: no reply within ~step_timeout 3.00 s: robots [0, 64) on swarm/commands', reason)
        self.assertIn('~first_id 64 is beyond the swarm of 64 robots (valid: [0, 63])', err)

    def test_gap_names_the_serving_nodes(self):
        reason, _ = self.stopped(dict(MIXED, step_timeout=3.0), [controller(count=30), forager(first_id=32)])
        self.assertIn('robots [30, 32) on swarm/commands: no node serves them (/controller serves [0, 30), '
                      '/numpy_forager serves [32, 64))', reason)

    def test_undeclared_external_controller(self):
        reason, _ = self.stopped(dict(controller='crw'), [controller(count=32), forager(first_id=32)])
        self.assertIn("tick 0: /numpy_forager [32, 64) runs controller 'numpy_forager', but the run is crw "
                      "(~controller)", reason)

    def test_declared_external_controller_nobody_runs(self):
        reason, _ = self.stopped(MIXED, [controller()])
        self.assertIn('tick 0: no node runs controller numpy_forager of the run crw+numpy_forager', reason)
        self.assertIn('every range runs crw: /controller [0, 64)', reason)

    def test_bad_parameters_exit_2(self):
        world_node = lambda **p: Node('swarm_forage', 'world_node', 'world', p)  # noqa: E731
        cases = [  # one node at a time: two nodes of one name would end each other
            (lambda: forager(wander_force=-1), '~wander_force must be in (0, 100] (got -1)'),
            (lambda: forager(count='abc'),
             "~count has the wrong type: got 'abc'; valid: a whole number in [0, 10000000]"),
            (lambda: forager(wander_forse=1),
             '~wander_forse (/numpy_forager/wander_forse) is not a parameter of numpy_forager; valid: first_id, '),
            (lambda: forager(hard_turn_speed=0.5),
             '~hard_turn_speed must be in (0, max_speed] m/s (got 0.5, max_speed 0.1)'),
            (lambda: world_node(external_controller='crw'), "~external_controller 'crw' is a controller of this build"),
            (lambda: world_node(external_controller='my-node'),
             "~external_controller must be a name of letters, digits and '_' (got 'my-node')"),
            (lambda: world_node(controller='numpy_forager'),
             "~controller: controller 'numpy_forager' is unknown; valid: crw, dpo, gp_dpo"),
        ]
        for start, message in cases:
            with self.subTest(message=message):
                node = start()
                try:
                    code = node.wait(timeout=120)
                    left = rospy.has_param(node.name)
                finally:
                    node.stop()
                self.assertEqual(code, 2, node.stderr())
                self.assertIn(message, node.stderr())
                self.assertFalse(left, '%s left its refused parameters on the master' % node.name)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'check_numpy_forager_ranges', TestNumpyForagerRanges, sys.argv)
