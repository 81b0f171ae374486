"""numpy_crw: swarm_forage's CRW as a Python controller run in process (docs/python-controllers.md).

The same forager as the C++ CRW (src/core/controllers/crw.cpp with forage_common.cpp and drive.cpp),
every robot of the batch at once with numpy: explore by a correlated random walk (a wander force whose
angle steps U[-step, step] each tick and wraps at the limit), pick up the first block after
min_explore_ticks, carry it home by phototaxis, wander in the nest, drop, leave the nest. Its one random
draw per robot and tick is the C++ CRW's (sensors.uniform[:, 0]); its trigonometry is numpy's, not the
core's fast approximations, so runs agree in distribution, not bit for bit."""
import math

import numpy as np

EXPLORE, PICKUP, TRANSPORT, NEST_WANDER, DROP, LEAVE_NEST = range(6)
GROUND_NEST, GROUND_BLOCK = 1, 2
PICKUP_DONE, DROP_DONE, JOINED = 1, 2, 8
REQUEST_PICKUP, REQUEST_DROP = 1, 2
NAME = 'swarm_forage_examples/numpy_crw'

# key: (low, high, low included, high included), as CrwConfig::validate.
RANGES = {
    'wander_step_deg': (0, 180, True, True), 'wander_limit_deg': (0, 180, False, True),
    'wander_circle_distance': (0, 1000, True, True), 'wander_force': (0, 100, False, True),
    'wander_free_scale': (0, 1, False, True), 'avoidance_force': (0, 100, True, True),
    'phototaxis_force': (0, 100, False, True), 'nest_wander_ticks': (0, 100000, True, True),
    'min_explore_ticks': (0, 100000, True, True), 'max_speed': (0, 1, False, True),
    'soft_turn_max_deg': (0, 180, False, False),
}


class NumpyCrw:
    display_name = 'numpy CRW'
    colour = 'tab:cyan'
    defaults = 'config/numpy_crw.yaml'
    states = ['explore', 'pickup', 'transport', 'nest_wander', 'drop', 'leave_nest']
    light_only_carrying = True  # phototaxis while carrying only, as CRW
    draws = 1                   # the wander step's uniform

    @staticmethod
    def validate(c):
        for key, (lo, hi, lo_in, hi_in) in RANGES.items():
            v = c[key]
            if not ((v >= lo if lo_in else v > lo) and (v <= hi if hi_in else v < hi)):
                raise ValueError('%s/%s must be in %s%g, %g%s (got %g)'
                                 % (NAME, key, '[' if lo_in else '(', lo, hi, ']' if hi_in else ')', v))
        if not c['wander_circle_distance'] < c['wander_circle_radius'] <= 10000:
            raise ValueError('%s/wander_circle_radius must be in (wander_circle_distance, 10000]' % NAME)
        if not 0 < c['hard_turn_speed'] <= c['max_speed']:
            raise ValueError('%s/hard_turn_speed must be in (0, max_speed] m/s' % NAME)

    def __init__(self, constants, seed, first_id, count, world):
        c = dict(constants)
        self.c = c
        self.step_max = math.radians(c['wander_step_deg'])
        self.limit = math.radians(c['wander_limit_deg'])
        self.soft_max = math.radians(c['soft_turn_max_deg'])
        self.transport_wander = 'transport_wander' in world['quirks']
        self.state = np.zeros(count, np.uint8)
        self.ticks = np.zeros(count, np.int64)
        self.angle = np.zeros(count, np.float32)
        self.drive_speed = np.zeros(count)  # cm/s: the mean wheel speed of the last drive command

    def save(self):
        return {'state': self.state, 'ticks': self.ticks, 'angle': self.angle, 'drive_speed': self.drive_speed}

    def load(self, arrays):
        self.state, self.ticks = arrays['state'], arrays['ticks']
        self.angle, self.drive_speed = arrays['angle'], arrays['drive_speed']

    def step(self, tick, s, out):
        c = self.c
        active = s.active != 0
        if s.events.any():
            joined = active & ((s.events & JOINED) != 0)  # a newcomer starts afresh
            for a in (self.state, self.ticks, self.angle, self.drive_speed):
                np.putmask(a, joined, 0)
        old, ticks = self.state, self.ticks
        ground, events = s.ground, s.events
        carrying = s.carried_block >= 0
        on_block, in_nest = ground == GROUND_BLOCK, ground == GROUND_NEST

        # Transitions from the state at the start of the tick (crw.cpp, deliveryTransition); masks and putmask,
        # not fancy indexing: a random mask costs numpy a mispredicted branch per element.
        explore, pickup, wander = old == EXPLORE, old == PICKUP, old == NEST_WANDER
        to_pickup = explore & on_block & ~carrying & (ticks >= c['min_explore_ticks'])
        picked = pickup & (carrying | ((events & PICKUP_DONE) != 0))
        missed = pickup & ~picked & ~on_block
        home = (old == TRANSPORT) & in_nest
        left_early, dropping = wander & ~in_nest, wander & in_nest & (ticks >= c['nest_wander_ticks'])
        drop = old == DROP
        dropped = drop & (~carrying | ((events & DROP_DONE) != 0))
        drop_out = drop & ~dropped & ~in_nest
        out_of_nest = (old == LEAVE_NEST) & ~in_nest
        new = old.copy()
        for mask, state in ((missed | out_of_nest, EXPLORE), (to_pickup, PICKUP), (picked | left_early | drop_out,
                            TRANSPORT), (home, NEST_WANDER), (dropping, DROP), (dropped, LEAVE_NEST)):
            np.putmask(new, mask & active, state)
        np.putmask(ticks, active & (picked | home | left_early | dropping | dropped | drop_out | out_of_nest), 0)

        moving = active & (new != PICKUP) & (new != DROP)
        transport, nest_wander, leave = new == TRANSPORT, new == NEST_WANDER, new == LEAVE_NEST
        threat = s.threatened != 0
        slow = transport & (np.abs(self.drive_speed) < 0.1) if self.transport_wander else np.zeros_like(transport)
        wanders = moving & (~transport | (slow & ~threat))

        # The wander force of the angle before its step (forage_common.cpp, wanderForce). Forces and wheels
        # in float32, as the sensors and the commands are: half the memory traffic of float64, and numpy's
        # float32 trigonometry is vectorised (its float64 one is not); the angle's walk in float64, as the core's.
        a = self.angle
        wfx = c['wander_circle_radius'] * np.cos(a) - c['wander_circle_distance']
        wfy = c['wander_circle_radius'] * np.sin(a)
        scale = wanders * (c['wander_force'] / np.sqrt(wfx * wfx + wfy * wfy))
        wx, wy = wfx * scale, wfy * scale
        nxt = a + (-self.step_max + (self.step_max + self.step_max) * s.uniform[:, 0])
        # fmod(next, limit) for limit <= |next| < 2 limit is next -+ limit; farther (no draw by default): fmod.
        turned = nxt - np.copysign(self.limit, nxt) * (np.abs(nxt) >= self.limit)
        if self.step_max >= self.limit:
            far = np.abs(nxt) >= 2 * self.limit
            if far.any():
                turned[far] = np.fmod(nxt[far], self.limit)
        np.putmask(self.angle, wanders, turned.astype(np.float32))

        # Avoidance and phototaxis (motionForce).
        ox, oy = s.obstacle_x, s.obstacle_y
        olen = np.sqrt(ox * ox + oy * oy)
        avoid = threat & (olen > 1e-9)
        k = avoid * (-c['avoidance_force'] / np.maximum(olen, np.float32(1e-9)))
        ax, ay = ox * k, oy * k
        lx, ly = s.light_x, s.light_y
        llen = np.sqrt(lx * lx + ly * ly)
        lit = llen > 1e-9  # NaN (no light traced for a robot that does not carry): False
        k = c['phototaxis_force'] / np.where(lit, llen, np.float32(1))
        px = np.where(lit, lx * k, np.float32(c['phototaxis_force']))
        py = np.where(lit, ly * k, np.float32(0))
        calm_slow = slow & ~threat
        sx, sy = wx + ax, wy + ay
        explore_scale = np.where(threat, np.float32(1), np.float32(c['wander_free_scale']))
        fx = sx * explore_scale
        fy = sy * explore_scale
        np.copyto(fx, sx, where=leave)
        np.copyto(fy, sy, where=leave)
        np.copyto(fx, wx, where=nest_wander)
        np.copyto(fy, wy, where=nest_wander)
        tx = px + np.where(calm_slow, wx, ax)
        ty = py + np.where(calm_slow, wy, ay)
        np.copyto(fx, tx, where=transport)
        np.copyto(fy, ty, where=transport)

        # Steering (drive.cpp, steer): soft turns up to soft_turn_max (always in transport), else in place.
        v = np.sqrt(fx * fx + fy * fy) * 0.01
        err = atan2(fy, fx)
        abs_err = np.abs(err)
        soft = (abs_err <= self.soft_max) | transport
        f = (self.soft_max - abs_err) / self.soft_max
        top, hard = c['max_speed'], c['hard_turn_speed']
        top, hard = np.float32(top), np.float32(hard)
        inner = np.minimum(np.maximum(np.where(soft, v * f, -hard), -top), top)
        outer = np.minimum(np.maximum(np.where(soft, v * (2.0 - f), hard), -top), top)
        go = moving & (v >= 1e-9)
        right_outer = (err >= 0) & go
        left_outer = (err < 0) & go
        out.left[:] = inner * (go & ~left_outer) + outer * left_outer
        out.right[:] = inner * (go & ~right_outer) + outer * right_outer
        out.request[:] = (new == PICKUP) * np.uint8(REQUEST_PICKUP) + (new == DROP) * np.uint8(REQUEST_DROP)
        out.state[:] = new

        # As the core finishes a robot: the drive command's speed is kept, the state clock advances.
        driven = active & (out.request == 0)
        np.putmask(self.drive_speed, driven, (out.left.astype(np.float64) + out.right) / 2.0 * 100.0)
        ticks += active
        self.state = new


def atan2(y, x):
    """atan2 as the core's fastAtan2 computes it (Cephes atan, util/fast_math.hpp), over arrays of the dtype of
    y and x: numpy's arctan2 is not vectorised and took a quarter of this controller's time."""
    ax, ay = np.abs(x), np.abs(y)
    swap = ay > ax
    lo, hi = np.minimum(ax, ay), np.maximum(ax, ay)
    mid = lo > 0.66 * hi
    t = np.where(mid, lo - hi, lo) / np.where(mid, lo + hi, np.where(hi > 0, hi, hi.dtype.type(1)))
    z = t * t
    p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z - 7.500855792314704667340e1) * z
         - 1.228866684490136173410e2) * z - 6.485021904942025371773e1
    q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z + 4.328810604912902668951e2) * z
         + 4.853903996359136964868e2) * z + 1.945506571482613964425e2
    base = np.where(mid, t.dtype.type(0.78539816339744830962), t.dtype.type(0))
    a = base + (t * z * p / q + t + np.where(mid, t.dtype.type(0.5 * 6.123233995736765886130e-17), t.dtype.type(0)))
    a = np.where(swap, t.dtype.type(1.57079632679489661923) - a, a)
    a = np.where(x < 0, t.dtype.type(3.14159265358979323846) - a, a)
    return np.copysign(a, y)
