# The Python package swarm_forage (src/swarm_forage), installed by catkin_python_setup() in CMakeLists.txt:
# `import swarm_forage.runs` after sourcing devel/setup.bash, next to the generated swarm_forage.msg.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=['swarm_forage'], package_dir={'': 'src'}))
