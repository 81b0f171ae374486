"""numpy_forager in process: the forager of the rospy node scripts/numpy_forager as a Python controller
kind (docs/python-controllers.md), run by controller_node, the nodelets and run_experiment alike.

A correlated random walk with obstacle avoidance, pick-up on a block, phototaxis home, drop in the nest,
leaving the nest away from the light; no loop over robots. Its draw is the rospy node's (draw 1 of the
robot's generator at the tick), handed over by the core as sensors.uniform[:, 0]."""
import math

import numpy as np

EXPLORE, PICKUP, TRANSPORT, DROP, LEAVE_NEST = range(5)
GROUND_NEST, GROUND_BLOCK = 1, 2
NAME = 'swarm_forage_examples/numpy_forager'
# key: (low, high, low included, high included), as the rospy node checks them.
RANGES = {
    'wander_step_deg': (0.0, 180.0, True, True), 'wander_force': (0.0, 100.0, False, True),
    'avoidance_force': (0.0, 100.0, True, True), 'phototaxis_force': (0.0, 100.0, False, True),
    'max_speed': (0.0, 1.0, False, True), 'soft_turn_max_deg': (0.0, 180.0, False, False),
    'hard_turn_speed': (0.0, 1.0, False, True),
}


def unit(x, y):
    """(x, y) / |(x, y)|, and (0, 0) where the length is 0 (or NaN)."""
    n = np.hypot(x, y)
    ok = n > 1e-9
    safe = np.where(ok, n, 1.0)
    return np.where(ok, x / safe, 0.0), np.where(ok, y / safe, 0.0)


class NumpyForager:
    display_name = 'numpy forager'
    colour = 'tab:olive'
    defaults = 'config/numpy_forager.yaml'
    states = ['explore', 'pickup', 'transport', 'drop', 'leave_nest']
    draws = 1

    @staticmethod
    def validate(c):
        for key, (lo, hi, lo_in, hi_in) in RANGES.items():
            v = c[key]
            if not ((v >= lo if lo_in else v > lo) and (v <= hi if hi_in else v < hi)):
                raise ValueError('%s/%s must be in %s%g, %g%s (got %g)'
                                 % (NAME, key, '[' if lo_in else '(', lo, hi, ']' if hi_in else ')', v))
        if c['hard_turn_speed'] > c['max_speed']:
            raise ValueError('%s/hard_turn_speed must be in (0, max_speed] m/s' % NAME)

    def __init__(self, constants, seed, first_id, count, world):
        self.c = dict(constants)
        self.state = np.zeros(count, np.uint8)

    def save(self):
        return {'state': self.state}

    def load(self, arrays):
        self.state = arrays['state']

    def step(self, tick, s, out):
        c = self.c
        s_ = self.state
        active = s.active != 0
        s_[active & ((s.events & 8) != 0)] = EXPLORE  # a newcomer starts afresh
        st = s_.copy()
        carrying = s.carried_block >= 0
        on_block, in_nest = s.ground == GROUND_BLOCK, s.ground == GROUND_NEST
        # Transitions, in order: a robot may take several in one tick.
        st[(st == EXPLORE) & carrying] = TRANSPORT
        st[(st == EXPLORE) & on_block] = PICKUP
        st[(st == PICKUP) & carrying] = TRANSPORT
        st[(st == PICKUP) & ~on_block] = EXPLORE
        st[(st == TRANSPORT) & in_nest] = DROP
        st[(st == DROP) & ~carrying] = LEAVE_NEST
        st[(st == DROP) & ~in_nest] = TRANSPORT
        st[(st == LEAVE_NEST) & ~in_nest] = EXPLORE
        st = np.where(active, st, s_)
        threatened = s.threatened != 0
        ax, ay = unit(-s.obstacle_x, -s.obstacle_y)
        ax, ay = ax * threatened * c['avoidance_force'], ay * threatened * c['avoidance_force']
        lx, ly = unit(s.light_x, s.light_y)
        lx = np.where((lx == 0) & (ly == 0), 1.0, lx)  # no light seen: straight on
        a = (2.0 * s.uniform[:, 0] - 1.0) * math.radians(c['wander_step_deg'])
        wx, wy = np.cos(a) * c['wander_force'], np.sin(a) * c['wander_force']
        home, leave = st == TRANSPORT, st == LEAVE_NEST
        fx = np.where(home, c['phototaxis_force'] * lx, wx - leave * c['phototaxis_force'] * lx) + ax
        fy = np.where(home, c['phototaxis_force'] * ly, wy - leave * c['phototaxis_force'] * ly) + ay
        # Steering as swarm_forage's drive: soft turns up to soft_turn_max, in place beyond (not carrying).
        v = np.hypot(fx, fy) * 0.01
        err = np.arctan2(fy, fx)
        soft_max = math.radians(c['soft_turn_max_deg'])
        f = (soft_max - np.abs(err)) / soft_max
        soft = (np.abs(err) <= soft_max) | home
        top, hard = c['max_speed'], c['hard_turn_speed']
        inner = np.clip(np.where(soft, v * f, -hard), -top, top)
        outer = np.clip(np.where(soft, v * (2.0 - f), hard), -top, top)
        go = (v >= 1e-9) & (st != PICKUP) & (st != DROP)
        out.left[:] = np.where(go, np.where(err >= 0, inner, outer), 0.0)
        out.right[:] = np.where(go, np.where(err >= 0, outer, inner), 0.0)
        out.request[:] = 0
        out.request[st == PICKUP] = 1
        out.request[st == DROP] = 2
        out.state[:] = st
        self.state = st
