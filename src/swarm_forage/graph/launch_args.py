"""The arguments a launch file declares that a caller may set: what `forage` accepts and what `sweep --graph`
may pass. A file it includes with pass_all_args receives every argument of the command line, so its arguments
count too, but for those the include sets itself."""
import xml.etree.ElementTree as ET


def file_args(path, own_only=False):
    """The settable <arg> elements of the launch file `path` (those without a fixed value), then those of each
    file it includes with pass_all_args (own_only: not those). Raises roslaunch's errors for an include that
    cannot be resolved, ET.ParseError and OSError."""
    root = ET.parse(path).getroot()
    args = [a for a in root.findall('arg') if a.get('value') is None]
    if own_only:
        return args
    for inc in root.findall('include'):
        if inc.get('pass_all_args') == 'true':
            import roslaunch.substitution_args  # here: a sweep without --graph never needs roslaunch
            taken = {a.get('name') for a in args + inc.findall('arg')}
            inner = file_args(roslaunch.substitution_args.resolve_args(inc.get('file')))
            args += [a for a in inner if a.get('name') not in taken]
    return args


def arg_names(path):
    """The names file_args finds."""
    return [a.get('name') for a in file_args(path)]
