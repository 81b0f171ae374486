# The Python package swarm_forage (src/swarm_forage) and its sub-packages, installed by catkin_python_setup() in
# CMakeLists.txt: `import swarm_forage.sweep.cli` after sourcing devel/setup.bash, next to the generated
# swarm_forage.msg.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

SUBPACKAGES = ('experiment', 'sweep', 'study', 'recommend', 'robustness', 'figures', 'bags', 'graph')

setup(**generate_distutils_setup(packages=['swarm_forage'] + ['swarm_forage.' + p for p in SUBPACKAGES],
                                 package_dir={'': 'src'}))
