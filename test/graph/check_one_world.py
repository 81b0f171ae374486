#!/usr/bin/env python3
"""One world per graph. A second world_node started into a running graph, or any other
publisher of world/sensors, stops the run with both node names: world/run_end incomplete, the bag renamed
*_incomplete.bag, forage exit 1 with the reason; a controller and a metrics_node follow one world only.
Before, the second world contaminated the run while forage said "run 0 complete"."""
import os
import shutil
import subprocess
import sys
import tempfile
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from swarm_forage.msg import CommandBatch, Performance, RunEnd, SensorBatch

FORAGE = ['rosrun', 'swarm_forage', 'forage', 'n_robots:=8', 'ticks:=1000000', 'seed:=1', 'record:=true',
          'wait_for_subscribers:=2', 'sample_interval:=100']
TIMEOUT = 180  # generous: the machine may be loaded; every wait ends on an event


class Graph:
    """forage in the background, its output collected as it comes."""

    def __init__(self, *args):
        self.proc = subprocess.Popen(FORAGE + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True)
        self.lines = []
        self.reader = threading.Thread(target=lambda: self.lines.extend(self.proc.stdout), daemon=True)
        self.reader.start()

    def finish(self):
        try:
            self.proc.wait(timeout=TIMEOUT)
        finally:
            if self.proc.poll() is None:
                self.proc.kill()
                self.proc.wait()
        self.reader.join(timeout=30)
        return self.proc.returncode, ''.join(self.lines)


class TestOneWorld(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_one_world')
        cls.performance, cls.commands, cls.ends, cls.logs = [], [], [], []
        rospy.Subscriber('/world/performance', Performance, cls.performance.append, queue_size=100000)
        rospy.Subscriber('/swarm/commands', CommandBatch, cls.commands.append, queue_size=100000)
        rospy.Subscriber('/world/run_end', RunEnd, cls.ends.append, queue_size=10)
        rospy.Subscriber('/rosout', Log, cls.logs.append, queue_size=10000)  # each node's, rosout or not

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_one_world_')
        for kept in (self.performance, self.commands, self.ends, self.logs):
            del kept[:]

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def wait_for(self, what, condition, graph=None):
        deadline = time.time() + TIMEOUT
        while not condition():
            self.assertLess(time.time(), deadline, 'no %s within %d s; log: %s; graph: %s' % (
                what, TIMEOUT, [(m.name, m.msg) for m in self.logs], ''.join(graph.lines) if graph else ''))
            time.sleep(0.05)

    def running(self, graph):
        """Waits until the graph's run has done 50 ticks."""
        self.wait_for('tick 50 of the first world', lambda: graph.proc.poll() is None and self.performance and
                      self.performance[-1].tick >= 50 or graph.proc.poll() is not None)
        self.assertIsNone(graph.proc.poll(), ''.join(graph.lines))

    def check_stopped(self, code, out, other):
        self.assertEqual(code, 1, out)
        self.assertIn('another node publishes /world/sensors in this graph: %s (this world: /world)' % other, out)
        self.assertIn('forage: run 0 stopped at tick', out)
        self.assertNotIn('run 0 complete', out)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, 'first.bag')), os.listdir(self.tmp))
        self.assertTrue(os.path.exists(os.path.join(self.tmp, 'first_incomplete.bag')), os.listdir(self.tmp))
        self.assertEqual(len(self.ends), 1)
        self.assertFalse(self.ends[0].complete)
        self.assertIn(other, self.ends[0].reason)
        # dynamic_reconfigure's servers have their own mutex: no deadlock warning.
        self.assertNotIn('provides its own mutex', out)

    def test_1_a_second_world_node_stops_the_run(self):
        graph = Graph('bag:=' + os.path.join(self.tmp, 'first.bag'))
        self.running(graph)
        second = subprocess.run(['rosrun', 'swarm_forage', 'world_node', '__name:=world2', '_n_robots:=8',
                                 '_seed:=5'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                timeout=TIMEOUT)
        self.assertFalse(rospy.has_param('/world2'), 'the refused world left its parameters on the master')
        code, out = graph.finish()
        print(out[-3000:])
        print(second.stdout)
        self.check_stopped(code, out, '/world2')
        # The second world refused to start, naming the first, and published nothing.
        self.assertEqual(second.returncode, 1, second.stdout)
        self.assertIn('another node publishes /world/sensors in this graph: /world (this world: /world2)',
                      second.stdout)
        self.assertEqual({p._connection_header['callerid'] for p in self.performance}, {'/world'})
        self.assertNotIn('never completed', out)  # metrics_node saw one world's ticks only

    def test_2_controller_and_metrics_follow_one_world_only(self):
        # No world_node here (its guard is test 1's): this test node is the world the controller and the
        # metrics_node follow first, `rostopic pub` a second one beside it.
        nodes = [subprocess.Popen(['rosrun', 'swarm_forage', kind, '__name:=one_world_' + kind],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                 for kind in ('controller_node', 'metrics_node')]
        sensors = rospy.Publisher('/world/sensors', SensorBatch, queue_size=1, latch=True)
        performance = rospy.Publisher('/world/performance', Performance, queue_size=1, latch=True)
        second = []
        try:
            self.wait_for('the controller subscribing', lambda: sensors.get_num_connections() >= 1)
            self.wait_for('the metrics_node subscribing', lambda: performance.get_num_connections() >= 2)
            # swarm_size 0: the controller takes this world as its own, yet has no robot of it to serve.
            sensors.publish(SensorBatch(run=0, tick=0, controller='crw', swarm_size=0))
            performance.publish(Performance(run=0, tick=0, swarm_size=8))
            me = rospy.get_name()  # rostest names this node after the test
            self.wait_for('the controller taking this world as its own',  # and serving none of its 0 robots
                          lambda: any('beyond the swarm of 0 robots' in m.msg for m in self.logs))
            for topic, kind, text in (('/world/sensors', 'SensorBatch',
                                       '{run: 77, tick: 0, seed: 5, controller: crw, swarm_size: 8}'),
                                      ('/world/performance', 'Performance', '{run: 0, tick: 1, swarm_size: 8}')):
                second.append(subprocess.Popen(['rosrun', 'rostopic', 'rostopic', 'pub', '-l', topic,
                                                'swarm_forage/' + kind, text, '__name:=second_' + kind],
                                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
            for node, words in (('/one_world_controller_node',
                                 'refused world/sensors from /second_SensorBatch: this controller serves the world %s'),
                                ('/one_world_metrics_node',
                                 'ignored world/performance from /second_Performance: following the world %s')):
                self.wait_for('%s refusing the second world' % node,
                              lambda: any(words % me in m.msg for m in self.logs if m.name == node))
            self.assertEqual([c.tick for c in self.commands if c.run == 77], [])
        finally:
            for p in second + nodes:
                p.terminate()
                p.wait(timeout=60)
            sensors.unregister()
            performance.unregister()
            for kind in ('controller_node', 'metrics_node'):
                if rospy.has_param('/one_world_' + kind):
                    rospy.delete_param('/one_world_' + kind)

if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'one_world', TestOneWorld, sys.argv)
