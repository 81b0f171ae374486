"""Files a test makes, removed when it ends: pure Python, so that the unit tier needs no ROS graph."""
import atexit
import os
import shutil


def removed_at_exit(path):
    """`path`, a folder the test made or named for its nodes, removed when the test process ends (a test
    leaves nothing behind, passed or failed)."""
    atexit.register(shutil.rmtree, path, True)
    return path


def write(folder, name, text):
    """Writes `text` to folder/name; returns the path."""
    path = os.path.join(folder, name)
    with open(path, 'w') as f:
        f.write(text)
    return path
