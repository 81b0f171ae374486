#!/usr/bin/env python3
"""Invalid parameters stop each node at start-up (exit code 2) with a message naming the parameter
and its valid range."""
import os
import subprocess
import sys
import tempfile
import unittest

import rospy
import rostest
from graph_helpers import removed_at_exit  # noqa: E402

CASES = [
    # node, private parameters, words the message must contain
    ('world_node', {'n_robots': 0}, ['~n_robots', '[1,']),
    ('world_node', {'n_robots': -5}, ['~n_robots', '[1,']),
    ('world_node', {'n_robots': 100000}, ['n_robots', '[1, 5181]', '32x16']),
    ('world_node', {'n_robots': 'many'}, ['~n_robots', 'wrong type']),
    ('world_node', {'arena': 'nope'}, ['~arena', 'nope', '32x16, 64x32, 96x48']),
    ('world_node', {'arena': '@BAD_YAML@'}, ['malformed YAML']),
    ('world_node', {'arena': '@ZERO_WIDTH@'}, ['width', 'must be in']),
    ('world_node', {'arena': '/nonexistent/arena.yaml'}, ['cannot be read']),
    ('world_node', {'arena': '@TYPO_YAML@'}, ["unknown key 'widht'", 'valid keys: name, width, height, blocks']),
    ('world_node', {'n_robots': 1e9}, ['~n_robots must be in [1, 10000000]']),
    ('world_node', {'n_robots': 64.5}, ['~n_robots must be a whole number']),
    ('world_node', {'bag': '/tmp/a.bag', 'bag_dir': '/tmp'}, ['~bag and ~bag_dir']),
    ('world_node', {'outcome': '/proc/no_such_dir/outcome.yaml'}, ['~outcome', 'cannot be appended']),
    ('world_node', {'compression': 'zip'}, ['~compression', 'zip', 'none, lz4, bz2']),
    ('world_node', {'tf_robots': 100}, ['~tf_robots', '[0, 64]', 'got 100']),
    ('world_node', {'tf_robots': [0, -3]}, ['~tf_robots', 'entry 1 is not an id']),
    ('world_node', {'tf_robots': 'some'}, ['~tf_robots', 'a count in [0, 64]']),
    ('world_node', {'threads': -1}, ['~threads', '[0, 256]']),
    ('world_node', {'markers_rate': -2.0}, ['~markers_rate', 'must be in']),
    ('world_node', {'diag_wait_warn': 2.0, 'diag_wait_error': 1.0}, ['~diag_wait_error', '[2, 3600]', 'got 1']),
    ('world_node', {'diagnostic_period': 0.0}, ['~diagnostic_period', '[0.05, 60]']),
    ('metrics_node', {'diag_behind_warn': -1}, ['~diag_behind_warn', 'must be in']),
    ('world_node', {'controller': 'foo'}, ['~controller', 'foo', 'crw']),
    ('world_node', {'ticks': 0}, ['~ticks', '[1,']),
    ('world_node', {'step_timeout': -1.0}, ['~step_timeout', 'must be in']),
    ('world_node', {'mode': 'fast'}, ['~mode', 'lockstep, realtime']),
    ('world_node', {'los_radius': -1}, ['~los_radius', '[0, 100]']),
    ('controller_node', {'controller': 'foo'}, ['~controller', 'crw']),
    ('controller_node', {'crw/wander_force': -1.0}, ['~crw/wander_force', 'must be in']),
    ('controller_node', {'crw/wander_forse': 9.0}, ['~crw/wander_forse is not a crw constant', 'valid keys:',
                                                    'wander_force']),
    ('controller_node', {'dpo/pheromone_decay': 1.5}, ['~dpo/pheromone_decay', '[0, 1)']),
    ('controller_node', {'gp_dpo/estimates': 'guess'}, ['~gp_dpo/estimates', 'ideal, time_varying']),
    ('controller_node', {'gp_dpo/abort_reactivity': -1.0}, ['~gp_dpo/abort_reactivity', '[0, 100]']),
    ('world_node', {'controller': 'gp_dpo', 'cache/size_fraction': 0.9}, ['cache', 'size_fraction', 'must be in']),
    ('environment_node', {'waveform': 'zigzag'}, ['~waveform', 'step_up']),
    ('environment_node', {'beta': 2.0}, ['~beta', '[-1, 1]']),
    ('environment_node', {'waveform': 'step_up', 'beta': 0.4, 'alpha': 20000.0},
     ['~alpha 20000 s is not within the run', '10000 s', 'step_up']),
    ('environment_node', {'waveform': 'sine', 'frequency': 0.0}, ['~frequency', '(0, 1000]']),
    ('environment_node', {'waveform': 'square', 'beta': 0.6, 'offset': 0.6}, ['offset', 'amplitude', '<= 1']),
    ('metrics_node', {'sample_interval': 0}, ['~sample_interval', '[1,']),
    ('metrics_node', {'definitions': 'authors'}, ['~definitions', 'paper, authors_code_2019']),
    ('metrics_node', {'dtw_band': -1}, ['~dtw_band', '[0,']),
    ('metrics_node', {'library': '/proc/no_such_library'}, ['~library', '/proc/no_such_library']),
]


class TestBadParams(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_bad_params')
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_bad_params_'))
        cls.bad_yaml = os.path.join(cls.tmp, 'bad.yaml')
        with open(cls.bad_yaml, 'w') as f:
            f.write('width: [32, 16\nheight: 16\n')
        cls.typo_yaml = os.path.join(cls.tmp, 'typo.yaml')
        with open(cls.typo_yaml, 'w') as f:
            f.write('name: typo\nwidht: 32\nheight: 16\n')
        cls.zero_width = os.path.join(cls.tmp, 'zero.yaml')
        with open(cls.zero_width, 'w') as f:
            f.write('name: zero\nwidth: 0\nheight: 16\nblocks: 50\n')

    def check(self, index, node, params, words):
        name = 'bad_%d' % index
        for key, value in params.items():
            if isinstance(value, str):
                value = {'@BAD_YAML@': self.bad_yaml, '@ZERO_WIDTH@': self.zero_width,
                         '@TYPO_YAML@': self.typo_yaml}.get(value, value)
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.run(['rosrun', 'swarm_forage', node, '__name:=' + name], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=60, text=True)
        rospy.delete_param('/' + name)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        for word in words:
            self.assertIn(word, proc.stdout)


def _make_case(index, node, params, words):
    return lambda self: self.check(index, node, params, words)


# One test per case, named after the node and the parameter.
for _i, (_node, _params, _words) in enumerate(CASES):
    _key = '_'.join(k.replace('/', '_') for k in _params)
    setattr(TestBadParams, 'test_%02d_%s_%s' % (_i, _node, _key), _make_case(_i, _node, _params, _words))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_bad_params', TestBadParams, sys.argv)
