"""Prints the latest /diagnostics status of every node, like `rosdiagnostic` would.

Debian 12's rosdiagnostic has no executable, and its diagnostic_aggregator cannot start (its package.xml
is not installed), so there is no /diagnostics_agg: this gathers /diagnostics for a while instead, keeps
each status's latest message and prints them worst first.

examples:
    rosrun swarm_forage health            # every status, one line each
    rosrun swarm_forage health -d         # with their key/values
    rosrun swarm_forage health -f -l 1    # follow: WARN and worse, reprinted each period
"""
import argparse
import sys

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

LEVELS = {DiagnosticStatus.OK: " OK  ", DiagnosticStatus.WARN: "WARN ", DiagnosticStatus.ERROR: "ERROR",
          DiagnosticStatus.STALE: "STALE"}


def print_statuses(statuses, min_level, detail):
    for status in sorted(statuses.values(), key=lambda s: (-s.level, s.name)):
        level = status.level
        if level < min_level:
            continue
        print("[ {} ] {} - {}".format(LEVELS.get(level, str(level)), status.name, status.message))
        if detail:
            for kv in status.values:
                print("    - {}: {}".format(kv.key, kv.value))
    sys.stdout.flush()


def main(argv=None):
    parser = argparse.ArgumentParser(prog="health", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-l", "--level", type=int, default=0, help="lowest level shown (OK=0, WARN=1, ERROR=2; default 0)")
    parser.add_argument("-d", "--detail", action="store_true", help="print every status's key/values")
    parser.add_argument("-f", "--follow", action="store_true", help="keep printing, once per --wait")
    parser.add_argument("--wait", type=float, default=2.5, help="seconds to gather statuses (wall) [2.5]")
    parser.add_argument("--topic", default="/diagnostics", help="the topic to gather (default /diagnostics)")
    args = parser.parse_args(rospy.myargv()[1:] if argv is None else argv)
    rospy.init_node("health", anonymous=True, disable_signals=False)
    statuses = {}
    rospy.Subscriber(args.topic, DiagnosticArray,
                     lambda msg: statuses.update({s.name: s for s in msg.status}), queue_size=100)
    while not rospy.is_shutdown():
        rospy.rostime.wallsleep(args.wait)
        if not statuses:
            print("no status on {} within {} s".format(args.topic, args.wait))
        else:
            print_statuses(dict(statuses), args.level, args.detail)
        if not args.follow:
            return 0 if statuses else 1
        print("-" * 60)
    return 0

