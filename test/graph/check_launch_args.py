#!/usr/bin/env python3
"""Every foraging.launch argument reaches its node, as a separate process and as a nodelet (nodelet:=true):
each argument, set to a value other than its default, changes the graph roslaunch would start (a parameter of
a node, or a node itself), and changes it the same way in both modes. The two modes start the same nodes (by
name, class and required flag) with the same parameters; nodelet mode adds only the manager. view.launch and
record.launch pass every argument through. roslaunch's own loader builds each graph; nothing is started."""
import os
import sys
import unittest
import xml.etree.ElementTree as ET

import roslaunch.config
import roslaunch.xmlloader
import rostest

PACKAGE = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..')
LAUNCH = os.path.join(PACKAGE, 'launch')
NODES = {'world', 'controller', 'environment', 'metrics'}
MANAGER = 'swarm'

# A value other than the default for every argument, with the arguments it needs to matter. A new argument
# of foraging.launch must be added here (test_every_argument_is_covered).
VALUES = {
    'controller': ('gp_dpo', {}),
    'n_robots': ('7', {}),
    'arena': ('64x32', {}),
    'seed': ('9', {}),
    'ticks': ('1234', {}),
    'waveform': ('sine', {}),
    'beta': ('0.25', {}),
    'alpha': ('12.5', {}),
    'frequency': ('0.02', {}),
    'phase': ('0.5', {}),
    'offset': ('0.1', {}),
    'target': ('speed', {}),
    'series': ('/tmp/profile.csv', {}),
    'mode': ('realtime', {}),
    'real_time_factor': ('3.0', {}),
    'record': ('true', {}),
    'library': ('/tmp/library', {}),
    'results': ('/tmp/results', {'record': 'true'}),
    'bag': ('/tmp/run.bag', {'record': 'true'}),
    'overwrite': ('true', {}),
    'label': ('key1', {}),
    'compression': ('bz2', {}),
    'record_every': ('50', {}),
    'outcome': ('/tmp/outcome.yaml', {}),
    'definitions': ('authors_code_2019', {}),
    'metrics': ('false', {}),
    'sample_interval': ('250', {}),
    'step_timeout': ('9.5', {}),
    'exit_when_done': ('false', {}),
    'metrics_csv': ('/tmp/metrics.csv', {}),
    'required': ('false', {}),
    'wait_for_subscribers': ('2', {}),
    'serialize_block_ops': ('true', {}),
    'model': ('swarm_forage', {}),
    'quirks': ('heading_estimate,light_occlusion', {}),
    'population/death': ('0.01', {}),
    'population/birth': ('0.02', {}),
    'population/malfunction': ('0.03', {}),
    'population/repair': ('0.04', {}),
    'population/max_size': ('64', {}),
    'markers_rate': ('0', {}),
    'tf_robots': ('[0, 5, 9]', {}),
    'threads': ('2', {}),
    'controller_constants': ('{gp_dpo: {estimates: time_varying}}', {}),
    'noise': ('{all: {model: uniform, level: 0.01}, ground: {level: 0.05}}', {}),
    'controller_count': ('16', {}),
    'external_controller': ('numpy_forager', {}),
}


def declared(name):
    """The arguments a caller may set in launch/NAME, by name."""
    root = ET.parse(os.path.join(LAUNCH, name)).getroot()
    return {a.get('name'): a for a in root.findall('arg') if a.get('value') is None}


def graph(name, args):
    """What roslaunch would start for launch/NAME with `args`: {node name: (class, required)} and {parameter: value},
    the same description whichever way a node runs (its executable swarm_forage/X_node or the nodelet
    swarm_forage/X loaded into the manager)."""
    config = roslaunch.config.ROSLaunchConfig()  # without roscore.xml's parameters (they run rosversion)
    roslaunch.xmlloader.XmlLoader().load(os.path.join(LAUNCH, name), config, verbose=False,
                                         argv=['%s:=%s' % kv for kv in sorted(args.items())])
    nodes = {}
    for n in config.nodes:
        if n.package == 'nodelet' and n.args.split()[:1] == ['load']:
            _, cls, manager = n.args.split()
            assert manager == MANAGER, '%s loads into %s' % (n.name, manager)
        elif n.package == 'nodelet':
            cls = 'nodelet ' + n.args
        else:
            cls = '%s/%s' % (n.package, n.type[:-len('_node')] if n.type.endswith('_node') else n.type)
        nodes[n.name] = (cls, n.required)
    params = {k: p.value for k, p in config.params.items()}
    return nodes, params


def without_manager(g):
    nodes, params = g
    return ({k: v for k, v in nodes.items() if k != MANAGER},
            {k: v for k, v in params.items() if not k.startswith('/%s/' % MANAGER)})


def changes(base, other):
    """What differs between two graphs: nodes and parameters, as sorted (name, before, after)."""
    out = []
    for a, b in zip(base, other):
        out += [(k, a.get(k), b.get(k)) for k in sorted(set(a) | set(b)) if a.get(k) != b.get(k)]
    return out


class TestLaunchArgs(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.args = declared('foraging.launch')
        cls.base = {m: graph('foraging.launch', {'nodelet': m}) for m in ('false', 'true')}

    def test_every_argument_is_covered(self):
        self.assertEqual(sorted(set(self.args) - {'nodelet'}), sorted(VALUES), 'arguments this test does not set')
        for name, arg in self.args.items():
            self.assertTrue(arg.get('doc'), 'foraging.launch argument %s has no doc' % name)

    def test_two_modes_start_the_same_graph(self):
        nodes, params = self.base['false']
        self.assertEqual(nodes, {n: ('swarm_forage/' + n, True) for n in NODES})
        self.assertEqual(self.base['true'][0][MANAGER], ('nodelet manager', True))
        self.assertEqual(without_manager(self.base['true']), (nodes, params))
        plugins = ET.parse(os.path.join(PACKAGE, 'nodelet_plugins.xml')).getroot()
        self.assertEqual({c.get('name') for c in plugins.iter('class')}, {'swarm_forage/' + n for n in NODES})

    def test_every_argument_reaches_its_node_in_both_modes(self):
        for name, (value, needs) in VALUES.items():
            with self.subTest(argument=name):
                seen = {}
                for mode in ('false', 'true'):
                    base = graph('foraging.launch', dict(needs, nodelet=mode))
                    g = graph('foraging.launch', dict(needs, nodelet=mode, **{name: value}))
                    seen[mode] = changes(without_manager(base), without_manager(g))
                    self.assertTrue(seen[mode], '%s:=%s changes nothing with nodelet:=%s' % (name, value, mode))
                    for key, _, _ in seen[mode]:
                        self.assertIn(key.split('/')[1] if key.startswith('/') else key, NODES, key)
                self.assertEqual(seen['false'], seen['true'], '%s reaches the graph differently as nodelets' % name)
                print('%s:=%s -> %s' % (name, value, ', '.join(k for k, _, _ in seen['false'])))

    def test_every_node_starts_with_only_this_launch_parameters(self):
        # clear_params: what an earlier launch or a hand left in a node's namespace (a noise key, a bag) is
        # deleted before this launch sets its own parameters.
        for mode, manager in (('false', set()), ('true', {'/%s/' % MANAGER})):
            config = roslaunch.config.ROSLaunchConfig()
            roslaunch.xmlloader.XmlLoader().load(os.path.join(LAUNCH, 'foraging.launch'), config, verbose=False,
                                                 argv=['nodelet:=' + mode])
            self.assertEqual(set(config.clear_params), {'/%s/' % n for n in NODES} | manager, mode)
        config = roslaunch.config.ROSLaunchConfig()
        roslaunch.xmlloader.XmlLoader().load(os.path.join(LAUNCH, 'replay.launch'), config, verbose=False,
                                             argv=['bag:=/tmp/run.bag'])
        self.assertEqual(config.clear_params, ['/metrics/'])

    def test_record_launch_passes_every_argument(self):
        self.assertEqual(sorted(declared('record.launch')), ['bag'])
        for name, (value, needs) in list(VALUES.items()) + [('nodelet', ('true', {}))]:
            if name in ('record', 'bag'):
                continue
            with self.subTest(argument=name):
                args = dict(needs, bag='/tmp/run.bag', **{name: value})
                self.assertEqual(graph('record.launch', args), graph('foraging.launch', dict(args, record='true')))

    def test_view_launch_passes_every_argument(self):
        view = declared('view.launch')
        self.assertEqual(sorted(set(view) - set(self.args)), ['rviz_config'])
        defaults = {}
        for name, arg in view.items():
            if name != 'rviz_config':
                self.assertEqual(arg.get('doc'), self.args[name].get('doc'), name)
                self.assertNotEqual(arg.get('default'), self.args[name].get('default'), '%s: same default' % name)
                defaults[name] = arg.get('default')
        for name, (value, needs) in list(VALUES.items()) + [('nodelet', ('true', {}))]:
            with self.subTest(argument=name):
                args = dict(needs, **{name: value})
                nodes, params = graph('view.launch', args)
                self.assertEqual(nodes.pop('rviz')[0], 'rviz/rviz')
                self.assertEqual((nodes, params), graph('foraging.launch', dict(defaults, **args)))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'launch_args', TestLaunchArgs, sys.argv)
