#!/usr/bin/python3
"""py_servo_controller.py: a cell-pressure controller of the virtual rig in
Python (rospy), obeying the same topic/service contract as the C++
servo_controller_node (DESIGN §6, include/virtual_triaxial/ros/
servo_controller_node.h). It exists to prove that controllers are swappable
across languages: dem_node cannot tell the two apart.

Parameters (private, `~`):
  target                 (required) stress target of every controlled axis [Pa], >= 0
  strategy               "proportional" (the only law implemented here)
  gain                   0.5     dimensionless servo gain g in (0, 1]
  max_dimensionless_rate 1e-4    cap on |eps'| = |rate| T0 of the commands (T0 from get_info)
  axes                   [0, 1]  cell axes to control (0 = x, 1 = y, 2 = z)
  owner                  the node's name; the name used with claim_axes
  start_enabled          true    claim the axes at start (retried every 0.2 s wall)
Bad parameters: the node exits with status 1, naming the parameter.

Wiring (relative to the node's namespace, i.e. the rig's): subscribes
`stress`, publishes `cell_command` and `servo_state`, calls dem_node's
`get_info`, `claim_axes`, `release_axes`. The claim is made only once both
topic connections to dem_node exist, so in lockstep mode no state of a
claimed tick is missed. Calls whose answer is lost are made again
(rig_service_calls.py); the newest state received while enabled and
unclaimed is answered once a claim succeeds, if its tick is after the
claim's (dem_node ran an earlier claim whose answer was lost).

Per Stress message of tick k (k > the tick returned by claim_axes): targets
from the ramp at the message's simulation time, then the stiffness-normalised
proportional law of include/virtual_triaxial/control/proportional_servo.h,
per controlled axis i with e_i = sigma_ii - target_i (compression positive):
    rate_i = -g e_i / (K_i * control_period)                 [1/s]
    if K_i <= 0 or g |e_i| >= K_i control_period max_rate:  rate_i = -sign(e_i) max_rate (saturated)
    e_i == 0: rate_i = 0
then a CellCommand with tick k for the controlled axes and a ServoState.

Services, in the node's PRIVATE namespace (e.g. /servo/enable):
set_confining_pressure (target for every controlled axis, linear ramp over
ramp_seconds of SIMULATION time), set_axis_targets, set_axes (change the
controlled axes; the test protocol node uses it between stages), enable
(claim + start; "not claimed yet (why), retrying" while the claim is
pending, as the C++ node answers), disable (release_axes), get_memory / set_memory (the
law's memory for a rig checkpoint and its resume: none, the proportional
law keeps no state between updates). Refusals name the field.

Timing: only wall-clock threads and message stamps are used (no rospy.Timer,
which would follow /clock under use_sim_time and stall while dem_node is
paused). Units SI, compression positive (DESIGN §2).
"""
import math
import sys
import threading
import time
import warnings

import rospy
from rig_service_calls import call_idempotent, enabled_not_claimed_yet, release_axes
from std_srvs.srv import Trigger, TriggerResponse
from virtual_triaxial.msg import CellCommand, ServoState, Stress
from virtual_triaxial.srv import (ClaimAxes, GetInfo, GetMemory, GetMemoryResponse, ReleaseAxes, SetAxisTargets,
                                  SetAxisTargetsResponse, SetConfiningPressure, SetConfiningPressureResponse,
                                  SetMemory, SetMemoryResponse, SetServoAxes, SetServoAxesResponse)

NODE = "py_servo_controller"


def valid_stress_target(v):
    return isinstance(v, (int, float)) and math.isfinite(v) and v >= 0.0


def axes_text(axes):
    return "[" + ", ".join(str(a) for a in axes) + "]"


class TargetRamp:
    """Per-axis linear ramp in simulation time (as src/ros/target_ramp.cpp)."""

    def __init__(self, target):
        # per axis: [from, to, start, duration]
        self.axes = [[target, target, 0.0, 0.0] for _ in range(3)]

    @staticmethod
    def _at(a, t):
        frm, to, start, dur = a
        if dur <= 0.0 or t >= start + dur:
            return to
        if t <= start:
            return frm
        return frm + (to - frm) * ((t - start) / dur)

    def ramp(self, axis, target, t, duration):
        a = self.axes[axis]
        self.axes[axis] = [self._at(a, t), target, t, duration if duration > 0.0 else 0.0]

    def value(self, t):
        return [self._at(a, t) for a in self.axes]


class ProportionalLaw:
    """The law of proportional_servo.h / src/control/proportional_servo.cpp."""

    name = "proportional"

    def __init__(self, gain, max_strain_rate, mask):
        if not (math.isfinite(gain) and 0.0 < gain <= 1.0):
            raise ValueError("gain must be in (0, 1], got %r" % gain)
        if not (math.isfinite(max_strain_rate) and max_strain_rate > 0.0):
            raise ValueError("max_strain_rate [1/s] must be finite and > 0, got %r" % max_strain_rate)
        self.gain = gain
        self.max_strain_rate = max_strain_rate
        self.mask = mask

    def update(self, dt, stress, stiffness, targets):
        """Returns (rates[3], errors[3], saturated[3]); raises ValueError on bad input."""
        if not (math.isfinite(dt) and dt > 0.0):
            raise ValueError("dt must be finite and > 0, got %r" % dt)
        g, cap = self.gain, self.max_strain_rate
        rates = [0.0, 0.0, 0.0]
        errors = [0.0, 0.0, 0.0]
        sat = [False, False, False]
        for i in range(3):
            if not self.mask[i]:
                continue
            s, k = stress[i], stiffness[i]
            if not (math.isfinite(s) and math.isfinite(k)):
                raise ValueError("stress/stiffness.%s is not finite" % "xyz"[i])
            e = s - targets[i]
            errors[i] = e
            if e == 0.0:
                continue
            # same expression order as the C++: (-g * e) / (k * dt)
            if k > 0.0 and g * abs(e) < k * dt * cap:
                rates[i] = -g * e / (k * dt)
            else:
                rates[i] = -cap if e > 0.0 else cap
                sat[i] = True
        return rates, errors, sat


def fail(msg):
    rospy.logfatal("%s: %s", NODE, msg)  # printed on stderr too
    sys.exit(1)


def number_param(name, default=None, required=False):
    key = "~" + name
    if not rospy.has_param(key):
        if required:
            fail("%s: required" % key)
        return default
    v = rospy.get_param(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        fail("%s: must be a number, got %r" % (key, v))
    return float(v)


class PyServoController:
    def __init__(self):
        self.lock = threading.RLock()
        self.read_parameters()
        self.law = None
        self.claimed = False
        self.last_time = 0.0
        self.last_tick = 0
        self.has_tick = False
        self.claim_tick = 0
        self.pending = None  # newest Stress received while enabled and not claimed
        self.last_wait_reason = ""

        # Subscriber first so dem_node sees our connection as early as possible.
        # Publishers without a queue: publish() writes in the calling thread (no
        # hand-off to a writer thread), the lowest latency for lockstep.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.command_pub = rospy.Publisher("cell_command", CellCommand, queue_size=None, tcp_nodelay=True,
                                               latch=True)  # a late dem_node connection still gets the last answer
            self.state_pub = rospy.Publisher("servo_state", ServoState, queue_size=None, tcp_nodelay=True)
        self.stress_sub = rospy.Subscriber("stress", Stress, self.on_stress, queue_size=100, tcp_nodelay=True)
        # Proxies made once (resolved in the node's namespace); each call looks the service up.
        self.info_srv = rospy.ServiceProxy("get_info", GetInfo)
        self.claim_srv = rospy.ServiceProxy("claim_axes", ClaimAxes)
        self.release_srv = rospy.ServiceProxy("release_axes", ReleaseAxes)
        self.services = [
            rospy.Service("~set_confining_pressure", SetConfiningPressure, self.on_set_confining_pressure),
            rospy.Service("~set_axis_targets", SetAxisTargets, self.on_set_axis_targets),
            rospy.Service("~set_axes", SetServoAxes, self.on_set_axes),
            rospy.Service("~enable", Trigger, self.on_enable),
            rospy.Service("~disable", Trigger, self.on_disable),
            rospy.Service("~get_memory", GetMemory, self.on_get_memory),
            rospy.Service("~set_memory", SetMemory, self.on_set_memory),
        ]
        # reused message objects (publish() serialises at once in synchronous mode)
        self.cmd = CellCommand()
        self.cmd.owner = self.owner
        self.cmd.axes = list(self.axes)
        self.state = ServoState()
        self.state.strategy = ProportionalLaw.name
        self.state.controlled = list(self.mask)
        self.state.gain = self.gain
        retry = threading.Thread(target=self.retry_loop, name="claim_retry", daemon=True)
        retry.start()

    # ---- parameters -----------------------------------------------------------------
    def read_parameters(self):
        strategy = rospy.get_param("~strategy", "proportional")
        if strategy != "proportional":
            fail("~strategy: unknown strategy '%s' (known: proportional)" % strategy)
        self.owner = rospy.get_param("~owner", rospy.get_name())
        if not isinstance(self.owner, str) or not self.owner:
            fail("~owner: must be a non-empty string")
        self.gain = number_param("gain", 0.5)
        if not (math.isfinite(self.gain) and 0.0 < self.gain <= 1.0):
            fail("~gain: must be in (0, 1], got %r" % self.gain)
        self.max_dimensionless_rate = number_param("max_dimensionless_rate", 1e-4)
        if not (math.isfinite(self.max_dimensionless_rate) and self.max_dimensionless_rate > 0.0):
            fail("~max_dimensionless_rate: must be a finite number > 0")
        target = number_param("target", required=True)
        if not valid_stress_target(target):
            fail("~target: must be a finite number >= 0 Pa")
        self.ramp = TargetRamp(target)
        axes = rospy.get_param("~axes", [0, 1])
        if not isinstance(axes, list) or any(isinstance(a, bool) or not isinstance(a, int) for a in axes):
            fail("~axes: must be a list of integers (0 = x, 1 = y, 2 = z)")
        if not axes:
            fail("~axes: no axis given")
        self.mask = [False, False, False]
        for a in axes:
            if a < 0 or a > 2:
                fail("~axes: %d is not 0, 1 or 2" % a)
            if self.mask[a]:
                fail("~axes: axis %d listed twice" % a)
            self.mask[a] = True
        self.axes = axes
        self.enabled = bool(rospy.get_param("~start_enabled", True))

    # ---- claim / release ------------------------------------------------------------------
    def try_claim(self):
        """get_info + claim_axes; '' on success, else why not (yet). Caller holds the lock."""
        if self.stress_sub.get_num_connections() == 0 or self.command_pub.get_num_connections() == 0:
            return "waiting for dem_node's stress / cell_command connections"
        try:
            info, _ = call_idempotent(self.info_srv)
        except (rospy.ServiceException, rospy.ROSException) as e:
            return "get_info not available yet (%s)" % e
        try:
            law = ProportionalLaw(self.gain, self.max_dimensionless_rate / info.t0, self.mask)
        except (ValueError, ZeroDivisionError) as e:
            return "servo: %s" % e
        self.law = law
        self.last_time = info.time
        try:
            r, _ = call_idempotent(self.claim_srv, owner=self.owner, axes=list(self.axes))
        except (rospy.ServiceException, rospy.ROSException) as e:
            return "claim_axes not available yet (%s)" % e
        if not r.success:
            return "claim_axes refused: " + r.message
        self.claim_tick = r.tick
        self.claimed = True
        self.state.max_strain_rate = law.max_strain_rate
        rospy.loginfo("%s: '%s' controls axes %s (proportional, gain %g, |eps'| <= %g, T0 %.4g s)", NODE,
                      self.owner, axes_text(self.axes), self.gain, self.max_dimensionless_rate, info.t0)
        # A state that came while the claim was pending, for a tick dem_node
        # waits on us for (an earlier claim of ours took effect, its answer lost).
        pending, self.pending = self.pending, None
        if pending is not None and pending.tick > self.claim_tick:
            self.answer(pending)
        return ""

    def release(self):
        """release_axes; '' on success. Asked even without a claim recorded
        here (dem_node may list one whose answer was lost); then a refusal
        means none, as we think. Caller holds the lock."""
        answered, why = release_axes(self.release_srv, self.owner, self.axes, self.claimed)
        if answered:
            self.claimed = False  # refused means we do not own them any more either
            self.pending = None
        return why

    def retry_loop(self):
        while not rospy.is_shutdown():
            time.sleep(0.2)  # wall clock on purpose
            with self.lock:
                if not self.enabled or self.claimed:
                    continue
                why = self.try_claim()
                if why and why != self.last_wait_reason:
                    rospy.loginfo("%s: %s; retrying", NODE, why)
                    self.last_wait_reason = why

    # ---- the control tick -----------------------------------------------------------------
    def on_stress(self, msg):
        with self.lock:
            self.last_time = msg.time
            tick = msg.tick
            previous = self.last_tick
            restarted = self.has_tick and tick <= previous
            self.last_tick = tick
            self.has_tick = True
            if restarted and self.claimed:
                rospy.logwarn("%s: tick %d after %d: dem_node restarted, claiming the axes again", NODE, tick,
                              previous)
                self.claimed = False
                self.pending = None
                return
            if self.enabled and not self.claimed:
                self.pending = msg  # answered if the claim, when made, makes it ours
            if not self.enabled or not self.claimed or self.law is None:
                return
            if tick <= self.claim_tick:  # a backlog from before the claim needs no answer
                return
            self.answer(msg)

    def answer(self, msg):
        """The law's command (and servo_state) for the state of tick msg.tick. Caller holds the lock."""
        tick = msg.tick
        s = msg.stress
        k = msg.stiffness
        targets = self.ramp.value(msg.time)
        try:
            rates, errors, sat = self.law.update(msg.control_period, (s[0], s[4], s[8]), k, targets)
        except ValueError as e:
            rospy.logerr_throttle(1.0, "%s: tick %d: no command: servo 'proportional': %s" % (NODE, tick, e))
            return
        cmd = self.cmd
        cmd.header = msg.header
        cmd.tick = tick
        cmd.strain_rate = [rates[a] for a in self.axes]
        self.command_pub.publish(cmd)

        st = self.state
        st.header = msg.header
        st.tick = tick
        st.enabled = self.enabled
        st.targets = [targets[i] if i in self.axes else 0.0 for i in range(3)]  # 0 on uncontrolled axes
        st.errors = errors
        st.saturated = sat
        st.strain_rate = rates
        self.state_pub.publish(st)

    # ---- services ---------------------------------------------------------------------------
    def on_set_confining_pressure(self, rq):
        with self.lock:
            if not valid_stress_target(rq.target):
                return SetConfiningPressureResponse(False,
                                                    "target: must be a finite number >= 0 Pa (compression positive)")
            if not (math.isfinite(rq.ramp_seconds) and rq.ramp_seconds >= 0.0):
                return SetConfiningPressureResponse(False,
                                                    "ramp_seconds: must be a finite number >= 0 (simulation seconds)")
            for a in self.axes:
                self.ramp.ramp(a, rq.target, self.last_time, rq.ramp_seconds)
            return SetConfiningPressureResponse(
                True, "target %f Pa on axes %s over %f s" % (rq.target, axes_text(self.axes), rq.ramp_seconds))

    def on_set_axis_targets(self, rq):
        with self.lock:
            axes = list(bytearray(rq.axes)) if isinstance(rq.axes, (bytes, bytearray)) else list(rq.axes)
            if not axes:
                return SetAxisTargetsResponse(False, "axes: no axis given")
            for a in axes:
                if a > 2 or not self.mask[a]:
                    return SetAxisTargetsResponse(
                        False, "axes: axis %d is not controlled by this servo (axes %s)" % (a, axes_text(self.axes)))
                if not valid_stress_target(rq.targets[a]):
                    return SetAxisTargetsResponse(False, "targets[%d]: must be a finite number >= 0 Pa" % a)
            if not (math.isfinite(rq.ramp_seconds) and rq.ramp_seconds >= 0.0):
                return SetAxisTargetsResponse(False, "ramp_seconds: must be a finite number >= 0 (simulation seconds)")
            for a in axes:
                self.ramp.ramp(a, rq.targets[a], self.last_time, rq.ramp_seconds)
            return SetAxisTargetsResponse(True, "targets set")

    def on_set_axes(self, rq):
        """As servo_controller_node's ~set_axes: release, take the new axes (new
        ones start at the current target of the first old axis), claim them
        again with a fresh law when enabled."""
        with self.lock:
            axes = list(bytearray(rq.axes)) if isinstance(rq.axes, (bytes, bytearray)) else list(rq.axes)
            if not axes:
                return SetServoAxesResponse(False, "axes: no axis given")
            mask = [False, False, False]
            for a in axes:
                if a > 2:
                    return SetServoAxesResponse(False, "axes: %d is not a cell axis (0 = x, 1 = y, 2 = z)" % a)
                if mask[a]:
                    return SetServoAxesResponse(False, "axes: axis %d listed twice" % a)
                mask[a] = True
            why = self.release()
            if why:
                rospy.logwarn("%s: set_axes: %s", NODE, why)
            base = self.ramp.value(self.last_time)[self.axes[0]]
            for a in axes:
                if not self.mask[a]:
                    self.ramp.ramp(a, base, self.last_time, 0.0)
            self.axes = axes
            self.mask = mask
            self.law = None
            self.cmd.axes = list(axes)
            self.state.controlled = list(mask)
            if not self.enabled:
                return SetServoAxesResponse(True, "axes %s (disabled: not claimed)" % axes_text(axes))
            why = self.try_claim()
            if why:
                return SetServoAxesResponse(False, "axes: " + why)
            return SetServoAxesResponse(True, "axes %s claimed" % axes_text(axes))

    def on_enable(self, _rq):
        with self.lock:
            self.enabled = True
            if self.claimed:
                return TriggerResponse(True, "already enabled; axes %s claimed" % axes_text(self.axes))
            why = self.try_claim()
            if not why:
                return TriggerResponse(True, "enabled; axes %s claimed" % axes_text(self.axes))
            return TriggerResponse(True, enabled_not_claimed_yet(why))

    def on_get_memory(self, _):
        """The proportional law keeps no state between updates: no numbers."""
        return GetMemoryResponse(True, "the proportional law keeps no memory", "proportional", [])

    def on_set_memory(self, rq):
        with self.lock:
            if not self.enabled or not self.claimed:
                return SetMemoryResponse(False, "memory: the servo is not running (enable it first; axes claimed)")
            if len(rq.memory) != 0:
                return SetMemoryResponse(False, "memory: the proportional law keeps no numbers, got %d" %
                                         len(rq.memory))
            return SetMemoryResponse(True, "restored 0 numbers")

    def on_disable(self, _rq):
        with self.lock:
            self.enabled = False
            why = self.release()
            return TriggerResponse(not why, "disabled; axes released" if not why else "disabled; " + why)


def main():
    rospy.init_node("servo")  # the launch file's name= overrides it
    PyServoController()
    rospy.spin()


if __name__ == "__main__":
    main()
