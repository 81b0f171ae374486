#!/usr/bin/env python3
"""A user's workspace (the one that holds this package, sourced in a clean environment, as a user sources
it) lists the built-in controller kinds and the example plugin and Python kinds, and nothing else: swarm_forage's test
fixtures live in a workspace of their own (docs/testing.md), so they are neither listed by
`run_experiment --controllers` nor in an unknown name's "valid:" list, and no fixture's error is printed."""
import os
import re
import subprocess
import sys
import unittest

import rostest
import yaml

KINDS = ['crw', 'dpo', 'gp_dpo', 'swarm_forage_examples/levy', 'swarm_forage_examples/numpy_crw',
         'swarm_forage_examples/numpy_forager']


def workspace():
    """The devel (or install) space that holds this package: the first one on CMAKE_PREFIX_PATH with it."""
    for prefix in os.environ.get('CMAKE_PREFIX_PATH', '').split(':'):
        if os.path.isdir(os.path.join(prefix, 'share', 'swarm_forage_examples')) and \
                os.path.isfile(os.path.join(prefix, 'setup.bash')):
            return prefix
    raise AssertionError('no workspace with swarm_forage_examples on CMAKE_PREFIX_PATH: %s'
                         % os.environ.get('CMAKE_PREFIX_PATH'))


def as_user(command):
    """`command` (a shell line) after sourcing the workspace in an environment of nothing else."""
    env = {k: os.environ[k] for k in ('HOME', 'ROS_HOME', 'ROS_LOG_DIR') if k in os.environ}
    env.update(PATH='/usr/bin:/bin', PYENV_VERSION='system')
    return subprocess.run(['bash', '-c', 'source %s/setup.bash && %s' % (workspace(), command)], env=env,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=240)


class UserListing(unittest.TestCase):
    def test_controllers_lists_the_built_ins_and_the_example_only(self):
        proc = as_user('rosrun swarm_forage run_experiment --controllers')
        self.assertEqual(proc.returncode, 0, proc.stderr)
        self.assertEqual([k['name'] for k in yaml.safe_load(proc.stdout)], KINDS)
        self.assertEqual(proc.stderr, '')

    def test_an_unknown_name_lists_the_same_kinds(self):
        proc = as_user('rosrun swarm_forage run_experiment controller:=my_pkg/Nope ticks:=2')
        self.assertEqual(proc.returncode, 2, proc.stderr)
        self.assertRegex(proc.stderr, "controller 'my_pkg/Nope' is unknown; valid: %s(?![,/\\w])"
                         % re.escape(', '.join(KINDS)))
        self.assertNotIn('fixture', proc.stderr)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'user_listing', UserListing, sys.argv)
