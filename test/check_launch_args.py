#!/usr/bin/env python3
"""view.launch declares every foraging.launch argument, with the same documentation, and passes each one
through to its include of foraging.launch; it declares no argument of its own but rviz_config."""
import os
import sys
import unittest
import xml.etree.ElementTree as ET

import rostest

LAUNCH = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'launch')


class TestLaunchArgs(unittest.TestCase):
    def test_view_passes_every_foraging_arg(self):
        foraging = {a.get('name'): a for a in ET.parse(os.path.join(LAUNCH, 'foraging.launch')).getroot()
                    .findall('arg') if a.get('default') is not None}
        view = ET.parse(os.path.join(LAUNCH, 'view.launch')).getroot()
        declared = {a.get('name'): a for a in view.findall('arg')}
        include = [i for i in view.findall('include') if i.get('file').endswith('/launch/foraging.launch')]
        self.assertEqual(len(include), 1)
        passed = {a.get('name'): a.get('value') for a in include[0].findall('arg')}
        self.assertEqual(sorted(set(foraging) - set(declared)), [], 'foraging.launch arguments view.launch lacks')
        self.assertEqual(sorted(set(declared) - set(foraging)), ['rviz_config'])
        for name, arg in foraging.items():
            self.assertEqual(passed.get(name), '$(arg %s)' % name, name)
            self.assertEqual(declared[name].get('doc'), arg.get('doc'), name)
        print('%d arguments in step' % len(foraging))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'launch_args', TestLaunchArgs, sys.argv)
