"""Records the reference runs of rosbags/ and their expected metrics (rosbags/expected_metrics.yaml).

    rosrun swarm_forage make_reference_bags [--out DIR] [--model NAME]

Five short headless runs of the 32x16 arena (10,000 ticks, bz2, a snapshot every 2,500 ticks): CRW with
8 and 16 robots, DPO and GP-DPO with 16, and CRW with 16 under step_down beta = 0.4. Their expected
metrics are the tables run_tables computes over the folder (e and Z of CRW 8 -> 16, R and A of the
step_down run) and each run's P per 1,000-tick sample. Run it again after the model changes; the replay
test (rosbags.test) compares a fresh replay of every bag with what is written here. rosbags/ holds the
default model's runs, rosbags/swarm_forage/ the corrected model's (--model swarm_forage), which
rosbags.test remakes and compares message by message."""
import argparse
import csv
import os
import subprocess

import rosbag
import yaml

from swarm_forage.paths import PACKAGE

RUNS = [('crw_32x16_n8_null', ['controller:=crw', 'n_robots:=8']),
        ('crw_32x16_n16_null', ['controller:=crw', 'n_robots:=16']),
        ('dpo_32x16_n16_null', ['controller:=dpo', 'n_robots:=16']),
        ('gp_dpo_32x16_n16_null', ['controller:=gp_dpo', 'n_robots:=16']),
        ('crw_32x16_n16_step_down0.4', ['controller:=crw', 'n_robots:=16', 'waveform:=step_down', 'beta:=0.4'])]
COMMON = ['arena:=32x16', 'seed:=1', 'ticks:=10000', 'record_every:=2500', 'compression:=bz2']
INTERVAL = 1000


def main(argv=None):
    p = argparse.ArgumentParser(prog='make_reference_bags', description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog='example:\n  rosrun swarm_forage make_reference_bags --out /tmp/refs   '
                                       '# then compare with rosbags/ (replaces the bags in --out)')
    p.add_argument('--out', default=os.path.join(PACKAGE, 'rosbags'),
                   help='folder for the bags and expected_metrics.yaml (default: %(default)s)')
    p.add_argument('--model', help='the model of every run (default: the default model)')
    a = p.parse_args(argv)
    out = os.path.abspath(a.out)
    model = ['model:=' + a.model] if a.model else []
    os.makedirs(out, exist_ok=True)
    for name, args in RUNS:
        bag = os.path.join(out, name + '.bag')
        if os.path.exists(bag):
            os.remove(bag)
        subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'bag:=' + bag] + COMMON + model + args,
                       check=True)
    tables = os.path.join(out, 'tables')
    subprocess.run(['rosrun', 'swarm_forage', 'run_tables', out, 'out:=' + tables,
                    'sample_interval:=%d' % INTERVAL], check=True)
    expected = {'sample_interval': INTERVAL, 'runs': {}, 'scalability': [], 'self_organization': [], 'flexibility': []}
    # Each run is a group of its own: a group's series belongs to the bag of the same identity.
    names = {}
    for name, _ in RUNS:
        with rosbag.Bag(os.path.join(out, name + '.bag')) as b:
            names.update((m.identity, name) for _, m, _ in b.read_messages(topics=['/world/run_info']))
    with open(os.path.join(tables, 'series.csv')) as f:
        for r in csv.DictReader(f):
            expected['runs'].setdefault(names[r['identity']], []).append(float(r['P_mean']))
    for name, keys in (('scalability', ('controller', 'waveform', 'N1', 'N2', 'e', 'phi')),
                       ('self_organization', ('controller', 'waveform', 'm_prev', 'm_i', 'Z_sum', 'Z_mean')),
                       ('flexibility', ('controller', 'waveform', 'beta', 'N', 'R', 'A'))):
        with open(os.path.join(tables, name + '.csv')) as f:
            for r in csv.DictReader(f):
                if r['valid'] == '1':
                    expected[name].append({k: (r[k] if k in ('controller', 'waveform') else float(r[k])) for k in keys})
    with open(os.path.join(out, 'expected_metrics.yaml'), 'w') as f:
        f.write('# Written by scripts/make_reference_bags from the bags next to it; checked by test/graph/rosbags.test.\n')
        yaml.safe_dump(expected, f, sort_keys=True)
    for f in os.listdir(tables):
        os.remove(os.path.join(tables, f))
    os.rmdir(tables)
    print('wrote %d bags and expected_metrics.yaml to %s' % (len(RUNS), out))
    return 0

