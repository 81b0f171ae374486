"""Where the package's own files are (config/, launch/, results/): the source folder this module is in, links
resolved (the checkout, as the scripts have always found it), else the installed package's."""
import os


def _package():
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
    if os.path.isfile(os.path.join(root, 'package.xml')):
        return root
    import rospkg  # an installed package: its share folder
    return rospkg.RosPack().get_path('swarm_forage')


PACKAGE = _package()
