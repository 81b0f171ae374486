#!/usr/bin/env python3
"""The rospy controller numpy_forager in lockstep runs of 64 robots: alone it delivers blocks and the bag
is complete; split across two nodes the run is the same robot for robot (its randomness is per robot);
next to controller_node the run is named by both controllers and its identity holds both constant sets."""
import os
import sys
import tempfile
import unittest

import rospy
import rostest

from forager_graph import controller, forager, read_bag, removed_at_exit, stop_all, wait_up, world

TICKS = 3000
EXTERNAL = dict(controller='numpy_forager', external_controller='numpy_forager', ticks=TICKS, record_every=100)


class TestNumpyForagerRun(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_numpy_forager_run')
        cls.dir = removed_at_exit(tempfile.mkdtemp(prefix='numpy_forager_run_'))

    def run_graph(self, name, world_params, nodes):
        """Runs a world with `nodes` (started first) to its end; the bag's messages by topic."""
        bag = os.path.join(self.dir, name + '.bag')
        wait_up(nodes)
        w = world(bag, **world_params)
        try:
            code = w.wait(timeout=900)
        finally:
            stop_all([w] + nodes)
        self.assertEqual(code, 0, 'world_node failed:\n' + w.stderr() + ''.join(n.stderr() for n in nodes))
        return read_bag(bag)

    def check_complete(self, run, controller_name, ticks):
        info, end = run['/world/run_info'][0], run['/world/run_end'][-1]
        self.assertTrue(end.complete, end.reason)
        self.assertEqual((end.ticks_done, end.ticks), (ticks, ticks))
        self.assertEqual(info.controller, controller_name)
        self.assertEqual([p.tick for p in run['/world/performance']], list(range(ticks)))
        return info

    def test_alone_delivers_and_a_split_changes_nothing(self):
        whole = self.run_graph('whole', EXTERNAL, [forager()])
        info = self.check_complete(whole, 'numpy_forager', TICKS)
        self.assertIn('numpy_forager/wander_force=9', info.controller_constants)
        self.assertNotIn('crw/', info.controller_constants)
        delivered = whole['/world/performance'][-1].cumulative
        self.assertGreater(delivered, 0, 'no block delivered in %d ticks' % TICKS)
        statuses = whole['/swarm/status']
        self.assertEqual(len(statuses), TICKS)
        for s in statuses:
            self.assertEqual((s.controller, s.first_id, s.count, s.swarm_size), ('numpy_forager', 0, 64, 64))
            self.assertEqual(sum(s.state_counts), 64)
            self.assertEqual(bool(s.constants), s.tick == 0, 'constants belong in the first status only')
        self.assertEqual(list(statuses[0].state_names), ['explore', 'pickup', 'transport', 'drop', 'leave_nest'])
        self.assertTrue(any(s.state_counts[2] > 0 for s in statuses), 'no robot ever carried a block home')
        print('numpy_forager alone: %d blocks in %d ticks' % (delivered, TICKS))

        split = self.run_graph('split', EXTERNAL, [forager('forager_low', count=32), forager('forager_high', first_id=32)])
        split_info = self.check_complete(split, 'numpy_forager', TICKS)
        self.assertEqual(split_info.identity, info.identity, 'both nodes report the same constants')
        perf = [(p.tick, p.delivered, p.cumulative, p.carrying) for p in whole['/world/performance']]
        self.assertEqual([(p.tick, p.delivered, p.cumulative, p.carrying) for p in split['/world/performance']], perf)
        robots = [(r.tick, r.x, r.y, r.theta, r.carried_block) for r in whole['/world/robots']]
        self.assertEqual(len(robots), TICKS // 100)
        self.assertEqual([(r.tick, r.x, r.y, r.theta, r.carried_block) for r in split['/world/robots']], robots)
        ranges = sorted({(s.first_id, s.count) for s in split['/swarm/status']})
        self.assertEqual(ranges, [(0, 32), (32, 32)])

    def test_next_to_controller_node(self):
        ticks = 500
        mixed = self.run_graph('mixed', dict(controller='crw', external_controller='numpy_forager', ticks=ticks),
                               [controller(count=32), forager(first_id=32)])
        info = self.check_complete(mixed, 'crw+numpy_forager', ticks)
        words = info.controller_constants.split()
        crw = [w for w in words if w.startswith('crw/')]
        self.assertTrue(crw and words[:len(crw)] == crw, 'the announced kind first: ' + info.controller_constants)
        self.assertIn('numpy_forager/wander_force=9', words[len(crw):])
        served = {(s.controller, s.first_id, s.count) for s in mixed['/swarm/status']}
        self.assertEqual(served, {('crw', 0, 32), ('numpy_forager', 32, 32)})


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'check_numpy_forager_run', TestNumpyForagerRun, sys.argv)
