#!/usr/bin/env python3
"""The Levy walker (src/levy.cpp) records bit-identical bags headless with one or two threads (its range
stepped in parts), in the node graph and in the nodelet graph: its randomness is a pure function of
(seed, robot, tick). Any split of the range gives the same commands: test_levy.cpp."""
import os
import sys

import rosbag
import rospkg
import rostest

SWARM_FORAGE = rospkg.RosPack().get_path('swarm_forage')
sys.path[:0] = [os.path.join(SWARM_FORAGE, 'test', 'helpers'), os.path.join(SWARM_FORAGE, 'test', 'graph')]
from run_helpers import RUN, RunsCase  # noqa: E402

LEVY = 'swarm_forage_examples/levy'


class LevyModes(RunsCase):
    PREFIX = 'swarm_forage_levy_modes_'
    TIMEOUT = 400

    def test_headless_threads_graph_split_and_nodelets_agree(self):
        words = ['controller:=' + LEVY, 'n_robots:=24', 'seed:=5', 'ticks:=4000']
        headless = self.bag('headless', *RUN, 'threads:=1', *words)
        with rosbag.Bag(headless) as bag:
            status = next(m for _, m, _ in bag.read_messages(topics=['/swarm/status']))
            carried = max(m.carrying for _, m, _ in bag.read_messages(topics=['/world/performance']))
        self.assertEqual(status.controller, LEVY)
        self.assertIn(LEVY + '/mu=2 ', status.constants)
        self.assertGreater(carried, 0, 'the walker picked up nothing')
        self.assertModesAgree(headless, words, LEVY)
        # The test can fail: another mu is another run.
        other = self.bag('other_mu', *RUN, 'threads:=1', LEVY + '/mu:=1.5', *words)
        self.assertOtherRun(headless, other)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'levy_modes', LevyModes)
