#!/usr/bin/env python3
"""Controller plugins, found by name: a plugin's headless run, graph run and nodelet graph record the
same bag (graph and nodelet graph bit-identical by scripts/compare_bags; headless equal to them but for
the publishers' header.seq, as check_headless_identity.py compares built-ins); an unknown name lists every controller available; a plugin
that throws when its batch is made or stepped, or sends a command the world cannot step (a NaN wheel
speed, an unknown request code), stops the run with its name, the tick and its message, in an incomplete
bag; a plugin's constants are validated like a built-in's and enter the run identity."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rostest
import yaml

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'test'))
from check_headless_identity import messages  # noqa: E402  (header.seq cleared)

PLUGIN = 'swarm_forage_examples/slow_crw'
COMMON = ['n_robots:=24', 'seed:=3']
GRAPH = ['metrics:=false', 'wait_for_subscribers:=0', 'record:=true']


def run(*cmd, timeout=300, stderr=subprocess.STDOUT):
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=stderr, text=True, timeout=timeout)
    return proc.returncode, proc.stdout


def run_end(path):
    with rosbag.Bag(path) as bag:
        ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
    return ends[-1]


class ControllerPlugins(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix='swarm_forage_plugins_')

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def folder(self, name):
        path = os.path.join(self.tmp, name)
        os.makedirs(path)
        return path

    def test_listing_names_built_ins_and_plugins_alike(self):
        code, out = run('rosrun', 'swarm_forage', 'run_experiment', '--controllers', stderr=subprocess.DEVNULL)
        self.assertEqual(code, 0, out)
        kinds = {k['name']: k for k in yaml.safe_load(out)}
        self.assertNotIn('swarm_forage_examples/fails_to_load', kinds)  # named on stderr instead
        for name in ('crw', 'dpo', 'gp_dpo', PLUGIN, 'swarm_forage_examples/fails_at_tick'):
            self.assertIn(name, kinds, out)
        slow = kinds[PLUGIN]
        self.assertEqual((slow['display_name'], slow['colour'], slow['plugin']), ('slow CRW', 'tab:brown', True))
        self.assertEqual(slow['constants'], ['crw', PLUGIN])
        self.assertTrue(os.path.isfile(slow['defaults']), slow)
        self.assertEqual(slow['defaults'], os.path.join(rospkg.RosPack().get_path('swarm_forage_examples'),
                                                        'config', 'slow_crw.yaml'))
        self.assertFalse(kinds['crw']['plugin'])
        self.assertTrue(os.path.isfile(kinds['crw']['defaults']), kinds['crw'])

    def test_headless_graph_and_nodelet_graph_record_the_same_bag(self):
        words = ['controller:=' + PLUGIN, 'ticks:=1500', 'waveform:=sine', 'beta:=0.3'] + COMMON
        bags = []
        for mode in ('headless', 'graph', 'nodelet'):
            bag = os.path.join(self.folder(mode), 'run.bag')
            if mode == 'headless':
                code, out = run('rosrun', 'swarm_forage', 'run_experiment', 'bag:=' + bag, *words)
            else:
                code, out = run('rosrun', 'swarm_forage', 'forage', 'bag:=' + bag, 'nodelet:=%s' % (mode == 'nodelet'),
                                *(GRAPH + words))
            self.assertEqual(code, 0, out[-3000:])
            bags.append(bag)
        end = run_end(bags[0])
        self.assertTrue(end.complete, end)
        with rosbag.Bag(bags[0]) as bag:
            status = next(m for _, m, _ in bag.read_messages(topics=['/swarm/status']))
            carried = max(m.carrying for _, m, _ in bag.read_messages(topics=['/world/performance']))
        self.assertEqual(status.controller, PLUGIN)
        self.assertIn(PLUGIN + '/speed_scale=0.5', status.constants)
        self.assertIn('crw/max_speed=', status.constants)  # it builds on crw
        self.assertGreater(carried, 0, 'the plugin picked up nothing')
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', bags[1], bags[2], '--ignore', '/world/provenance')
        self.assertEqual(code, 0, out)
        self.assertIn('identical', out)
        headless, graph = messages(bags[0]), messages(bags[1])
        del headless['/world/provenance'], graph['/world/provenance']
        self.assertEqual(sorted(headless), sorted(graph))
        for topic in headless:
            self.assertEqual(headless[topic], graph[topic], topic)
        print('slow_crw: headless, graph and nodelet graph identical; up to %d robots carrying' % carried)

    def test_constants_enter_the_identity_and_bag_names(self):
        out_dir = self.folder('identity')
        for scale in ('0.5', '0.4'):
            code, out = run('rosrun', 'swarm_forage', 'run_experiment', 'controller:=' + PLUGIN, 'ticks:=2',
                            'bag_dir:=' + out_dir, '%s/speed_scale:=%s' % (PLUGIN, scale), *COMMON)
            self.assertEqual(code, 0, out)
        names = sorted(os.listdir(out_dir))
        self.assertEqual(len(names), 2, names)  # two identities
        for n in names:
            self.assertTrue(n.startswith('swarm_forage_examples_slow_crw_32x16_n24_'), n)

    def test_unknown_name_lists_every_controller_available(self):
        listing = ('valid: crw, dpo, gp_dpo, swarm_forage_examples/fails_at_tick, swarm_forage_examples/fails_to_load, '
                   'swarm_forage_examples/fails_to_start')
        code, out = run('rosrun', 'swarm_forage', 'run_experiment', 'controller:=my_pkg/Nope', 'ticks:=2')
        self.assertEqual(code, 2, out)
        self.assertIn("controller 'my_pkg/Nope' is unknown; " + listing, out)
        self.assertIn(PLUGIN, out)
        code, out = run('rosrun', 'swarm_forage', 'forage', 'controller:=my_pkg/Nope', 'ticks:=2', 'metrics:=false')
        self.assertEqual(code, 2, out[-3000:])
        self.assertIn("controller 'my_pkg/Nope' is unknown; " + listing, out)

    def test_a_plugin_that_cannot_be_created_is_refused_at_start_up(self):
        why = "controller plugin 'swarm_forage_examples/fails_to_load' ("
        cause = 'failed to load: this plugin refuses to be created (a test fixture)'
        code, out = run('rosrun', 'swarm_forage', 'run_experiment', '--controllers')
        self.assertEqual(code, 0, out)
        self.assertIn(why, out)
        self.assertIn(cause, out)
        for cmd in (['run_experiment'], ['forage', 'metrics:=false']):
            code, out = run('rosrun', 'swarm_forage', *cmd, 'controller:=swarm_forage_examples/fails_to_load', 'ticks:=2')
            self.assertEqual(code, 2, out[-3000:])
            self.assertIn(why, out)
            self.assertIn(cause, out)

    def test_a_plugin_constant_is_checked_like_a_built_in_one(self):
        for words, message in (([PLUGIN + '/speed_scael:=0.3'], 'speed_scael is not a %s constant' % PLUGIN),
                               ([PLUGIN + '/speed_scale:=2'], PLUGIN + '/speed_scale must be in (0, 1]')):
            code, out = run('rosrun', 'swarm_forage', 'run_experiment', 'controller:=' + PLUGIN, 'ticks:=2', *words)
            self.assertEqual(code, 2, (words, out))
            self.assertIn(message, out)
        code, out = run('rosrun', 'swarm_forage', 'forage', 'controller:=' + PLUGIN, 'ticks:=2', 'metrics:=false',
                        'controller_constants:={%s: {speed_scael: 0.3}}' % PLUGIN)
        self.assertEqual(code, 2, out[-3000:])
        self.assertIn('speed_scael is not a %s constant' % PLUGIN, out)
        # roslaunch leaves parameters on the master: the bad one would refuse this test's later graphs.
        run('rosparam', 'delete', '/controller/' + PLUGIN)

    def stopped(self, plugin, tick, message, constants=None):
        """Headless, graph and nodelet graph: the run stops at `tick` naming the plugin and its message."""
        constants = constants or {}
        for mode in ('headless', 'graph', 'nodelet'):
            out_dir = self.folder('%s_%s' % (plugin.split('/')[1], mode))
            words = ['controller:=' + plugin, 'ticks:=50', 'bag:=' + os.path.join(out_dir, 'run.bag')] + COMMON
            if mode == 'headless':
                code, out = run('rosrun', 'swarm_forage', 'run_experiment', *words,
                                *('%s/%s:=%s' % (plugin, k, v) for k, v in constants.items()))
            else:
                code, out = run('rosrun', 'swarm_forage', 'forage', 'nodelet:=%s' % (mode == 'nodelet'),
                                'controller_constants:=' + yaml.safe_dump({plugin: constants}, default_flow_style=True).strip(),
                                *(GRAPH + words))
            self.assertEqual(code, 1, (mode, out[-3000:]))
            bags = glob.glob(os.path.join(out_dir, '*.bag'))
            self.assertEqual(len(bags), 1, (mode, os.listdir(out_dir), out[-2000:]))
            self.assertTrue(bags[0].endswith('_incomplete.bag'), bags)
            end = run_end(bags[0])
            self.assertFalse(end.complete)
            self.assertEqual(end.ticks_done, tick, (mode, end))
            for part in ("controller '%s'" % plugin, 'tick %d' % tick, message):
                self.assertIn(part, end.reason, mode)
            for part in ("controller '%s'" % plugin, message):  # and on the console
                self.assertIn(part, out, mode)
            print('%s, %s: %s' % (plugin, mode, end.reason))

    def test_a_plugin_that_throws_in_step_stops_the_run_naming_it(self):
        self.stopped('swarm_forage_examples/fails_at_tick', 7, 'failing on purpose (a test fixture)', {'tick': 7})

    def test_a_plugin_that_sends_a_nan_wheel_speed_stops_the_run_naming_it(self):
        self.stopped('swarm_forage_examples/sends_bad_commands', 6, 'sent the left wheel speed nan for robot 3 at tick 6',
                     {'tick': 6, 'robot': 3})

    def test_a_plugin_that_sends_an_unknown_request_stops_the_run_naming_it(self):
        plugin = 'swarm_forage_examples/sends_bad_commands'
        out_dir = self.folder('unknown_request')
        code, out = run('rosrun', 'swarm_forage', 'run_experiment', 'controller:=' + plugin, 'ticks:=50',
                        'bag_dir:=' + out_dir, plugin + '/tick:=4', plugin + '/robot:=20', plugin + '/request:=7',
                        *COMMON)
        self.assertEqual(code, 1, out)
        bags = os.listdir(out_dir)
        self.assertEqual(len(bags), 1, bags)
        self.assertTrue(bags[0].endswith('_incomplete.bag'), bags)
        end = run_end(os.path.join(out_dir, bags[0]))
        self.assertEqual((end.complete, end.ticks_done), (False, 4), end)
        for part in ("controller '%s'" % plugin, 'sent the request code 7 for robot 20 at tick 4',
                     'valid: 0 to 4'):
            self.assertIn(part, end.reason)
            self.assertIn(part, out)

    def test_a_plugin_whose_batch_cannot_be_made_stops_the_run_naming_it(self):
        self.stopped('swarm_forage_examples/fails_to_start', 0, 'this batch refuses to be made (a test fixture)')


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'controller_plugins', ControllerPlugins, sys.argv)
