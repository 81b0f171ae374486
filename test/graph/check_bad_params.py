#!/usr/bin/env python3
"""Invalid parameters stop each node at start-up (exit code 2) with a message naming the parameter
and its valid range."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rospkg
import rospy
import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit  # noqa: E402

CASES = [
    # node, private parameters, words the message must contain
    ('world_node', {'n_robots': 0}, ['~n_robots', '[1,']),
    ('world_node', {'n_robots': -5}, ['~n_robots', '[1,']),
    ('world_node', {'n_robots': 100000}, ['n_robots', '[1, 5181]', '32x16']),
    ('world_node', {'n_robots': 'many'}, ['~n_robots', 'wrong type', "got the text 'many'",
                                          'valid: a whole number in [1, 10000000]']),
    ('world_node', {'ticks_per_second': True}, ['~ticks_per_second', 'got the truth value true',
                                                'valid: a number in [0.001, 1000]']),
    ('world_node', {'exit_when_done': 3}, ['~exit_when_done', 'got the whole number 3', 'valid: true or false']),
    ('world_node', {'controller': 7}, ['~controller', 'got the whole number 7', 'valid: one of crw, dpo']),
    # Unknown parameters (item 7): a typo would leave the default in force unseen.
    ('world_node', {'n_robts': 5}, ['~n_robts (/bad_%d/n_robts) is not a parameter of world_node', 'valid: arena',
                                    'n_robots', 'label', 'overwrite', 'tf_robots', 'diag_wait_warn']),
    ('controller_node', {'cotroller': 'dpo'}, ['~cotroller', 'is not a parameter of controller_node',
                                               'controller, count, crw/, diagnostic_period, dpo/']),
    ('environment_node', {'wavform': 'sine'}, ['~wavform', 'is not a parameter of environment_node', 'waveform']),
    ('metrics_node', {'sample_intervall': 100}, ['~sample_intervall', 'is not a parameter of metrics_node',
                                                 'sample_interval']),
    ('world_node', {'cache/size_fractoin': 0.5}, ['~cache/size_fractoin', 'cache/size_fraction']),
    # Population dynamics: rates per tick in [0, 1], the maximum is the swarm size.
    ('world_node', {'population/death': -0.001}, ['~population/death must be in [0, 1]', 'got -0.001']),
    ('world_node', {'population/repair': float('nan')}, ['~population/repair must be in [0, 1]']),
    ('world_node', {'population/birth': 1.5}, ['~population/birth must be in [0, 1]', 'got 1.5']),
    ('world_node', {'population/death': 0.001, 'n_robots': 64, 'population/max_size': 32},
     ['population/max_size must be the swarm size n_robots = 64', 'got 32']),
    # FORDYCA's quirks: an unknown model or quirk is refused with the valid names, by both nodes.
    ('world_node', {'model': 'fordyca'}, ['~model', 'fordyca', 'valid: fordyca_2019, swarm_forage']),
    ('world_node', {'quirks': 'heading_estimate,light_occlusions'},
     ['~quirks', 'light_occlusions', 'transport_wander', 'dynamics2d_contacts']),
    ('controller_node', {'model': 'fordyca_2020'}, ['~model', 'valid: fordyca_2019, swarm_forage']),
    ('controller_node', {'quirks': 7}, ['~quirks must be quirk names', 'heading_estimate']),
    # One rule for beta without a waveform, at start-up as live (item 8).
    ('environment_node', {'beta': 0.3}, ['~beta has no effect on waveform null', 'got beta 0.3']),
    ('world_node', {'arena': '@DIR@'}, ['~arena: arena file', 'is a directory']),
    ('world_node', {'arena': '@LONG_NAME@'}, ['~arena: arena file', 'name must be 1 to 64 characters (got 5000']),
    ('world_node', {'arena': 'x' * 5000}, ['~arena', 'is unknown; valid: 32x16']),
    ('world_node', {'arena': 'nope'}, ['~arena', 'nope', '32x16, 64x32, 96x48']),
    ('world_node', {'arena': '@BAD_YAML@'}, ['malformed YAML']),
    ('world_node', {'arena': '@ZERO_WIDTH@'}, ['width', 'must be in']),
    ('world_node', {'arena': '/nonexistent/arena.yaml'}, ['~arena: arena file /nonexistent/arena.yaml does not exist']),
    ('world_node', {'arena': 'my_arena.yml'}, ['~arena: arena file my_arena.yml does not exist']),
    ('world_node', {'arena': '@TYPO_YAML@'}, ["unknown key 'widht'", 'valid keys: name, width, height, blocks']),
    # Each side within its range, but grids of tens of GiB: refused at start-up, not std::bad_alloc later.
    ('world_node', {'arena': '@HUGE@'}, ['~arena huge (10000 x 10000 m) needs an estimated', "GiB for the world's grids",
                                         'more than the limit of 4 GiB']),
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
    ('environment_node', {'waveform': 'square', 'beta': 0.6, 'offset': 0.6}, ['offset', 'beta', '<= 1']),
    ('metrics_node', {'sample_interval': 0}, ['~sample_interval', '[1,']),
    ('metrics_node', {'definitions': 'authors'}, ['~definitions', 'paper, authors_code_2019, authors_code_2020, authors_code']),
    ('metrics_node', {'dtw_band': -1}, ['~dtw_band', '[0,']),
    ('metrics_node', {'library': '/proc/no_such_library'}, ['~library', '/proc/no_such_library']),
    # Sensor and actuator noise (docs/robustness.md): levels, misread probabilities, models.
    ('world_node', {'noise/light/level': -0.01}, ['~noise/light/level must be in [0, 10]', 'got -0.01']),
    ('world_node', {'noise/heading/level': 4.0}, ['~noise/heading/level must be in [0, 3.14159', 'got 4']),
    ('world_node', {'noise/ground/level': 1.5}, ['~noise/ground/level must be in [0, 1]', 'got 1.5']),
    ('world_node', {'noise/all/level': -1}, ['~noise/all/level must be in [0, 1]', 'got -1']),
    ('world_node', {'noise/wheels/model': 'cauchy'}, ['~noise/wheels/model', "'cauchy' is not valid",
                                                      'gaussian, uniform']),
    ('world_node', {'noise/ground/model': 'uniform'}, ['~noise/ground/model', 'is not a parameter of world_node']),
    ('world_node', {'noise/proximity/level': 'high'}, ['~noise/proximity/level', "got the text 'high'"]),
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
        cls.long_name = os.path.join(cls.tmp, 'long.yaml')
        with open(cls.long_name, 'w') as f:
            f.write('name: %s\nwidth: 32\nheight: 16\n' % ('a' * 5000))
        cls.zero_width = os.path.join(cls.tmp, 'zero.yaml')
        with open(cls.zero_width, 'w') as f:
            f.write('name: zero\nwidth: 0\nheight: 16\nblocks: 50\n')
        cls.huge = os.path.join(cls.tmp, 'huge.yaml')
        with open(cls.huge, 'w') as f:
            f.write('name: huge\nwidth: 10000\nheight: 10000\nblocks: 50\n')

    def check(self, index, node, params, words):
        name = 'bad_%d' % index
        for key, value in params.items():
            if isinstance(value, str):
                value = {'@BAD_YAML@': self.bad_yaml, '@ZERO_WIDTH@': self.zero_width,
                         '@TYPO_YAML@': self.typo_yaml, '@DIR@': self.tmp,
                         '@LONG_NAME@': self.long_name, '@HUGE@': self.huge}.get(value, value)
            rospy.set_param('/%s/%s' % (name, key), value)
        proc = subprocess.run(['rosrun', 'swarm_forage', node, '__name:=' + name], stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, timeout=60, text=True)
        # A refused node deletes what it read too: the next node of that name starts from what it is given.
        self.assertFalse(rospy.has_param('/' + name), 'the refused %s left its parameters' % node)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        for word in words:
            self.assertIn(word.replace('%d', str(index)) if '%d' in word else word, proc.stdout)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp)

    def test_nodelet_refuses_an_unknown_parameter(self):
        # The same classes as nodelets: the world nodelet refuses ~n_robts and is not loaded.
        manager = subprocess.Popen(['rosrun', 'nodelet', 'nodelet', 'manager', '__name:=bad_manager'],
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        try:
            rospy.set_param('/bad_nodelet/n_robts', 5)
            load = subprocess.run(['rosrun', 'nodelet', 'nodelet', 'load', 'swarm_forage/world', 'bad_manager',
                                   '__name:=bad_nodelet'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                  text=True, timeout=120)
            self.assertFalse(rospy.has_param('/bad_nodelet'), 'the refused nodelet left its parameters')
            self.assertNotEqual(load.returncode, 0, load.stdout)
        finally:
            manager.terminate()
            out = manager.communicate(timeout=60)[0]
        self.assertIn('~n_robts (/bad_nodelet/n_robts) is not a parameter of world_node', out)

    def test_forage_refuses_an_undeclared_argument(self):
        # roslaunch ignores an argument its launch file does not declare: forage refuses it before starting.
        for args, words in ((['n_robot:=5'], ['foraging.launch declares no argument n_robot', 'valid: controller',
                                               'n_robots']),
                            (['nodelet:=true', 'n_robot:=5'], ['foraging.launch declares no argument n_robot']),
                            # record.launch takes foraging.launch's arguments but record, which it sets itself.
                            (['--launch', 'record.launch', 'bag:=/tmp/x.bag', 'nodelet:=true', 'record:=false'],
                             ['record.launch declares no argument record', 'valid: bag, controller', 'nodelet'])):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'forage'] + args, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            for word in words:
                self.assertIn(word, proc.stdout)
            self.assertNotIn('roslaunch', proc.stdout)  # nothing was started

    def test_run_experiment_refuses_non_finite_noise(self):
        # NaN and infinity cannot travel through the parameter server; run_experiment's words read them as
        # YAML does (.nan, .inf), and the same reader refuses them, naming the parameter and its range.
        for word, words in (('noise/position/level:=.nan', ['~noise/position/level must be in [0, 10]', 'nan']),
                            ('noise/light/level:=.inf', ['~noise/light/level must be in [0, 10]', 'inf']),
                            ('noise/ground/level:=-.inf', ['~noise/ground/level must be in [0, 1]'])):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', word, 'check:=true'],
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            for w in words:
                self.assertIn(w, proc.stdout)
        # The control: a good level passes the same check.
        good = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'noise/position/level:=0.01',
                               'check:=true'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=60)
        self.assertEqual(good.returncode, 0, good.stdout)

    def test_read_run_refuses_bad_input(self):
        # read_run (the offline metrics tool) reads NAME:=VALUE once, as the nodes read ~params: a bad or
        # unknown one exits 2 naming it and its valid range, a bag it cannot read exits 1; nothing on stdout.
        bag = os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'rosbags', 'crw_32x16_n8_null.bag')
        not_a_bag = os.path.join(self.tmp, 'not_a.bag')
        with open(not_a_bag, 'w') as f:
            f.write('not a bag\n')
        for args, code, words in (
                ([bag, 'sample_interval:=0'], 2, ['~sample_interval must be in [1, 100000000] (got 0)']),
                ([bag, 'sample_intervl:=5'], 2, ['sample_intervl is not a read_run parameter',
                                                 'valid: sample_interval, ticks']),
                ([bag, 'ticks:=maybe'], 2, ['~ticks has the wrong type', "got the text 'maybe'",
                                            'valid: true or false']),
                ([], 2, ['usage: read_run BAG']),
                ([not_a_bag], 1, [not_a_bag + ': not a readable bag']),
                ([os.path.join(self.tmp, 'missing.bag')], 1, ['missing.bag: not a readable bag'])):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'read_run'] + args, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True, timeout=120)
            self.assertEqual(proc.returncode, code, (args, proc.stderr))
            if args:
                self.assertEqual(proc.stdout, '', args)
            for word in words:
                self.assertIn(word, proc.stdout + proc.stderr, args)
        # The same bag with good parameters is read: the control that the cases above fail for their reason.
        good = subprocess.run(['rosrun', 'swarm_forage', 'read_run', bag, 'sample_interval:=500'],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
        self.assertEqual(good.returncode, 0, good.stderr)
        self.assertTrue(good.stdout.startswith('run,swarm_size,tick_end,interval_ticks,P,p,n_ca,s,final\n'))


def _make_case(index, node, params, words):
    return lambda self: self.check(index, node, params, words)


# One test per case, named after the node and the parameter.
for _i, (_node, _params, _words) in enumerate(CASES):
    _key = '_'.join(k.replace('/', '_') for k in _params)
    setattr(TestBadParams, 'test_%02d_%s_%s' % (_i, _node, _key), _make_case(_i, _node, _params, _words))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_bad_params', TestBadParams, sys.argv)
