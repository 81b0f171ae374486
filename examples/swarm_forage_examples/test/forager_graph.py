"""What the numpy_forager tests share: starting world_node, controller_node and numpy_forager nodes by
hand (each test reads their exit codes and stderr), and reading the bag a run recorded."""
import os
import subprocess
import sys
import tempfile
import time

import rosgraph
import rospkg
import rospy

# swarm_forage's own test helpers (open_bag, removed_at_exit): one copy of them.
sys.path.insert(0, os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'test', 'helpers'))
from graph_helpers import RunCollector, open_bag, removed_at_exit  # noqa: E402

__all__ = ['Node', 'RunCollector', 'controller', 'forager', 'read_bag', 'removed_at_exit', 'stop_all', 'wait_up',
           'world']


class Node:
    """One node started with rosrun; its stderr goes to a file (a full pipe would stall it)."""

    def __init__(self, pkg, exe, name, params):
        self.name = '/' + name
        if rospy.has_param(self.name):  # rosrun leaves _name:=value on the master: not an earlier node's
            rospy.delete_param(self.name)
        self.err = tempfile.TemporaryFile('w+')
        args = ['rosrun', pkg, exe, '__name:=' + name] + ['_%s:=%s' % kv for kv in sorted(params.items())]
        self.proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=self.err, text=True)

    def wait(self, timeout):
        return self.proc.wait(timeout=timeout)

    def stderr(self):
        self.err.seek(0)
        return self.err.read()

    def stop(self):
        """Ends the node if it still runs (it was started here: ended by its pid) and removes its
        parameters from the master (a later node of that name, e.g. a launch's, must not read them)."""
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        if rospy.has_param(self.name):
            rospy.delete_param(self.name)


def wait_up(nodes):
    """Waits until every controller node of `nodes` (Node, or a node's name) has advertised swarm/commands
    and swarm/status and subscribed to world/sensors. A Python node starts much slower than world_node,
    whose tick 0 waits only briefly for controller nodes it has not seen yet: start the world after this."""
    master = rosgraph.Master('/forager_graph')
    while True:
        publishers, subscribers, _ = master.getSystemState()
        pub, sub = dict(publishers), dict(subscribers)
        names = [n if isinstance(n, str) else n.name for n in nodes]
        if all(name in pub.get('/swarm/commands', []) and name in pub.get('/swarm/status', []) and
               name in sub.get('/world/sensors', []) for name in names):
            return
        for n in nodes:
            if not isinstance(n, str) and n.proc.poll() is not None:
                raise AssertionError('%s ended (exit %d) before it was up:\n%s' % (n.name, n.proc.returncode,
                                                                                   n.stderr()))
        time.sleep(0.1)


def world(bag='', **params):
    """world_node for a 64-robot lockstep run without an environment node, ending with its run."""
    p = dict(n_robots=64, seed=1, ticks=3000, use_environment='false', exit_when_done='true', step_timeout=60.0)
    p.update(params)
    if bag:
        p['bag'] = bag
    return Node('swarm_forage', 'world_node', 'world', p)


def forager(name='numpy_forager', **params):
    return Node('swarm_forage_examples', 'numpy_forager', name, params)


def controller(name='controller', **params):
    return Node('swarm_forage', 'controller_node', name, params)


def stop_all(nodes):
    for n in nodes:
        n.stop()


def read_bag(path):
    """{topic: [message, ...]} of a closed bag."""
    bag = open_bag(path)
    out = {}
    for topic, msg, _ in bag.read_messages():
        out.setdefault(topic, []).append(msg)
    bag.close()
    return out
