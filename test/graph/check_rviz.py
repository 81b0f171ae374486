#!/usr/bin/env python3
"""A real rviz under Xvfb draws the running graph: start Xvfb and rviz with config/rviz/swarm.rviz,
grab the screen with ImageMagick's `import`, and check that the picture is not blank and holds the
nest's green, the exploring robots' light blue and the walls' grey; with ~tasks (a GP-DPO graph), the
harvesters' magenta and the collectors' dark blue squares too. Keeps the PNG (~shot in ROS_HOME) for a
look."""
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy
import rospkg
import rospy
import rostest
from matplotlib import image


def start_xvfb():
    """Xvfb on a display it picks itself (-displayfd: two tests side by side never share one)."""
    read, write = os.pipe()
    xvfb = subprocess.Popen(['Xvfb', '-displayfd', str(write), '-screen', '0', '1280x720x24', '-nolisten', 'tcp'],
                            pass_fds=(write,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as f:
        display = f.readline().strip()
    if not display:
        raise RuntimeError('Xvfb did not start (exit code %s)' % xvfb.poll())
    return xvfb, ':' + display


def screenshot(path, env):
    """The screen as an RGB array (None when it cannot be grabbed); PNG24 keeps three channels even when
    the screen is still one colour."""
    if subprocess.run(['import', '-window', 'root', 'PNG24:' + path], env=env).returncode != 0:
        return None
    pixels = image.imread(path)
    return numpy.dstack([pixels] * 3) if pixels.ndim == 2 else pixels[:, :, :3]


class TestRviz(unittest.TestCase):
    def test_screenshot(self):
        rospy.init_node('check_rviz')
        rospy.wait_for_message('world/markers', rospy.AnyMsg, timeout=60)  # the graph runs
        x11_dir_existed = os.path.exists('/tmp/.X11-unix')
        runtime = tempfile.mkdtemp(prefix='swarm_forage_rviz_')  # Qt's XDG_RUNTIME_DIR, not /tmp/runtime-root
        xvfb, display = start_xvfb()
        env = dict(os.environ, DISPLAY=display, XDG_RUNTIME_DIR=runtime)
        config = os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'config', 'rviz', 'swarm.rviz')
        rviz = None
        try:
            rviz = subprocess.Popen(['rosrun', 'rviz', 'rviz', '-d', config, '__name:=rviz_check'], env=env,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            shot = os.path.join(os.environ.get('ROS_HOME', os.path.expanduser('~/.ros')), rospy.get_param('~shot', 'rviz_screenshot.png'))
            tasks = rospy.get_param('~tasks', False)
            pixels = None
            for _ in range(30):  # rviz takes a few seconds to come up and draw
                time.sleep(2.0)
                pixels = screenshot(shot, env)
                if pixels is not None and self.counts(pixels)['light blue'] > 200:
                    break
            self.assertIsNotNone(pixels, 'no screenshot could be taken')
            counts = self.counts(pixels)
            print('rviz screenshot %s: %s' % (shot, counts))
            self.assertGreater(float(pixels.std()), 0.05, 'the screenshot is blank')
            self.assertGreater(counts['nest green'], 2000)
            self.assertGreater(counts['light blue'], 200)  # exploring robots
            self.assertGreater(counts['wall grey'], 200)
            if tasks:
                self.assertGreater(counts['harvester magenta'], 50)
                self.assertGreater(counts['collector blue'], 50)
        finally:
            for p in (rviz, xvfb):
                if p is not None:
                    p.terminate()
                    try:
                        p.wait(timeout=10)
                    except subprocess.TimeoutExpired:
                        p.kill()
            shutil.rmtree(runtime, ignore_errors=True)
            if not x11_dir_existed:  # Xvfb made it for its socket; gone once empty
                try:
                    os.rmdir('/tmp/.X11-unix')
                except OSError:
                    pass

    @staticmethod
    def counts(px):
        px = px[:, 370:, :]  # the 3D view, right of the displays panel
        r, g, b = px[:, :, 0], px[:, :, 1], px[:, :, 2]
        return {
            # The nest (0.55, 0.85, 0.55) at alpha 0.6 on white.
            'nest green': int(numpy.sum((g > 0.8) & (r < 0.8) & (r > 0.6) & (b < 0.8) & (b > 0.6))),
            # Exploring robots (0.4, 0.7, 1.0), shaded.
            'light blue': int(numpy.sum((b > 0.7) & (r < 0.6) & (g > 0.45) & (g < 0.85) & (b - r > 0.3))),
            # The walls (0.3, 0.3, 0.3).
            'wall grey': int(numpy.sum((abs(r - g) < 0.03) & (abs(g - b) < 0.03) & (r > 0.2) & (r < 0.4))),
            # GP-DPO's task squares: harvesters (0.85, 0.1, 0.6), collectors (0.1, 0.2, 0.8), shaded.
            'harvester magenta': int(numpy.sum((r > 0.55) & (g < 0.3) & (b > 0.35) & (b < r))),
            'collector blue': int(numpy.sum((r < 0.25) & (g < 0.35) & (b > 0.5) & (b - g > 0.3))),
        }


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'rviz', TestRviz, sys.argv)
