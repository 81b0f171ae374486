"""Compares two bags message for message: topic, stamp and serialized bytes, in order.

usage: rosrun swarm_forage compare_bags A B [--ignore TOPIC ...]

A and B are two bags, or two folders whose *.bag files of the same names are compared pair by pair. Prints one
line per pair ("identical (N messages)" or the first difference) and exits 0 only when every pair is identical
(1 when one differs, 2 for bad arguments). A run's bags are identical for one seed in every mode (headless, node
graph, nodelet graph) and for any thread count, so this is how a refactor shows it moved code, not behaviour.
--ignore leaves topics out, e.g. /world/provenance, which names the code that made a record.

examples:
    rosrun swarm_forage compare_bags rosbags /tmp/refs --ignore /world/provenance
    rosrun swarm_forage compare_bags run_threads1.bag run_threads2.bag"""
import argparse
import os

import rosbag


def messages(path, ignore):
    with rosbag.Bag(path) as bag:
        return [(topic, t.to_nsec(), raw[1]) for topic, raw, t in bag.read_messages(raw=True) if topic not in ignore]


def difference(a, b, ignore):
    """'' when the bags hold the same messages, else the first difference."""
    ma, mb = messages(a, ignore), messages(b, ignore)
    for i, (x, y) in enumerate(zip(ma, mb)):
        if x != y:
            what = 'topic' if x[0] != y[0] else 'stamp' if x[1] != y[1] else 'content'
            return 'message %d differs in %s: %s at %.9f s vs %s at %.9f s' % (i, what, x[0], x[1] / 1e9, y[0], y[1] / 1e9)
    if len(ma) != len(mb):
        return '%d vs %d messages (the first %d are identical)' % (len(ma), len(mb), min(len(ma), len(mb)))
    return ''


def main(argv=None):
    p = argparse.ArgumentParser(prog='compare_bags', description=__doc__.split('\n\n')[0],
                                epilog=__doc__.split('\n\n', 2)[2], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('a')
    p.add_argument('b')
    p.add_argument('--ignore', nargs='+', default=[], metavar='TOPIC')
    args = p.parse_args(argv)
    if os.path.isdir(args.a) != os.path.isdir(args.b):
        p.error('give two bags or two folders')
    if os.path.isdir(args.a):
        names = sorted(f for f in os.listdir(args.a) if f.endswith('.bag'))
        if not names:
            p.error('%s holds no *.bag' % args.a)
        pairs = [(os.path.join(args.a, n), os.path.join(args.b, n)) for n in names]
    else:
        pairs = [(args.a, args.b)]
    differ = 0
    for a, b in pairs:
        try:
            why = difference(a, b, set(args.ignore))
        except (OSError, rosbag.ROSBagException) as e:
            why = 'cannot read: %s' % e
        print('%s: %s' % (os.path.basename(a), why or 'identical (%d messages)' % len(messages(a, set(args.ignore)))))
        differ += bool(why)
    return 1 if differ else 0

