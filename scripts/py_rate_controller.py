#!/usr/bin/python3
"""py_rate_controller.py: the axial strain-rate controller of the virtual rig
in Python (rospy), with the same topic/service contract as the C++
rate_controller_node (include/virtual_triaxial/ros/rate_controller_node.h).
It shows that users can write their own rate strategy: dem_node and the test
protocol node cannot tell the two apart. Start the rig with
    roslaunch virtual_triaxial protocol_rig.launch rate_node:=py_rate_controller.py

Parameters (private, `~`):
  owner   the node's name; the name used with claim_axes

Services (private): configure (ConfigureRate.srv), enable, disable
(std_srvs/Trigger), get_memory / set_memory (GetMemory.srv / SetMemory.srv:
the law's memory, the same numbers as the C++ node's, for a rig checkpoint
and `run_triaxial.sh --resume`), as the C++ node. Wiring: subscribes `moment_index`,
publishes `cell_command` and `rate_state`, calls dem_node's `claim_axes` and
`release_axes`.

The laws, written with the same floating-point operations in the same order
as the C++ (control/rate_strategy.h, control/adaptive_rate.h), so that both
nodes command the same rates bit for bit:
  fixed, predicted: the first rate, held.
  adaptive: with I the tick's I_mom and r the current rate [1/s]
    S <- S + (I - S) / n_s                   (S = I on the first tick)
    g = (target I_QS / S)^(1 / (kappa n_r))  (S = 0: g = 1 + c)
    g <- min(max(g, 1 / (1 + c)), 1 + c)
    r <- min(max(r g, eps'_min / T0), eps'_max / T0)
Units SI; rates compression positive; eps' = rate T0 (eq. 31).
"""
import math
import threading

import rospy
from rig_service_calls import call_idempotent, release_axes
from std_srvs.srv import Trigger, TriggerResponse
from virtual_triaxial.msg import CellCommand, MomentIndex, RateState
from virtual_triaxial.srv import (ClaimAxes, ConfigureRate, ConfigureRateResponse, GetMemory, GetMemoryResponse,
                                  ReleaseAxes, SetMemory, SetMemoryResponse)

NODE = "py_rate_controller"


def finite_positive(v):
    return math.isfinite(v) and v > 0.0


def check_adaptive(rq):
    """"" or "<field>: <reason>" (control/adaptive_rate.cpp's validate)."""
    if not (rq.target > 0.0 and rq.target <= 1.0):
        return "target: must be in (0, 1]"
    if not finite_positive(rq.min_dimensionless):
        return "min: must be finite and > 0"
    if not (math.isfinite(rq.max_dimensionless) and rq.max_dimensionless >= rq.min_dimensionless):
        return "max: must be finite and >= min"
    if not (rq.max_change > 0.0 and rq.max_change <= 1.0):
        return "max_change: must be in (0, 1]"
    if not (math.isfinite(rq.smoothing_ticks) and rq.smoothing_ticks >= 1.0):
        return "smoothing_ticks: must be >= 1"
    if not (math.isfinite(rq.response_ticks) and rq.response_ticks >= 1.0):
        return "response_ticks: must be >= 1"
    if not finite_positive(rq.sensitivity):
        return "sensitivity: must be finite and > 0"
    return ""


class HeldRate:
    """fixed / predicted: the first rate on every tick."""

    def __init__(self, name, rate0):
        self.name, self.rate = name, rate0

    def update(self, index, threshold):
        return self.rate

    def memory(self):
        return [self.rate]

    def restore(self, m):
        if len(m) != 1:
            raise ValueError("memory: '%s' keeps 1 number, got %d" % (self.name, len(m)))
        self.rate = m[0]


class AdaptiveRate:
    """The law of control/adaptive_rate.h (same expression order)."""

    name = "adaptive"

    def __init__(self, rq):
        self.p = rq
        self.lo_rate = rq.min_dimensionless / rq.t0
        self.hi_rate = rq.max_dimensionless / rq.t0
        self.rate = min(max(rq.rate0, self.lo_rate), self.hi_rate)
        self.smoothed = 0.0
        self.have_index = False

    def update(self, index, threshold):
        p = self.p
        if not (math.isfinite(index) and index >= 0.0):
            raise ValueError("moment_index: must be finite and >= 0")
        self.smoothed = self.smoothed + (index - self.smoothed) / p.smoothing_ticks if self.have_index else index
        self.have_index = True
        hi = 1.0 + p.max_change
        lo = 1.0 / hi
        if self.smoothed > 0.0:
            want = math.pow(p.target * threshold / self.smoothed, 1.0 / (p.sensitivity * p.response_ticks))
        else:
            want = hi
        g = min(max(want, lo), hi)
        self.rate = min(max(self.rate * g, self.lo_rate), self.hi_rate)
        return self.rate

    def memory(self):  # as control/adaptive_rate.h memory()
        return [self.rate, self.smoothed, 1.0 if self.have_index else 0.0]

    def restore(self, m):
        if len(m) != 3:
            raise ValueError("memory: 'adaptive' keeps 3 numbers, got %d" % len(m))
        self.rate, self.smoothed, self.have_index = m[0], m[1], m[2] != 0.0


class PyRateController:
    def __init__(self):
        self.owner = rospy.get_param("~owner", rospy.get_name())
        self.lock = threading.RLock()
        self.law = None
        self.axis, self.t0, self.threshold = 2, 0.0, 1e-3
        self.claimed, self.claim_tick = False, 0
        self.cmd_pub = rospy.Publisher("cell_command", CellCommand, queue_size=1000, latch=True)
        self.state_pub = rospy.Publisher("rate_state", RateState, queue_size=1000)
        self.claim = rospy.ServiceProxy("claim_axes", ClaimAxes)
        self.release_srv = rospy.ServiceProxy("release_axes", ReleaseAxes)
        rospy.Subscriber("moment_index", MomentIndex, self.on_index, queue_size=1000, tcp_nodelay=True)
        rospy.Service("~configure", ConfigureRate, self.on_configure)
        rospy.Service("~enable", Trigger, self.on_enable)
        rospy.Service("~disable", Trigger, self.on_disable)
        rospy.Service("~get_memory", GetMemory, self.on_get_memory)
        rospy.Service("~set_memory", SetMemory, self.on_set_memory)

    def on_get_memory(self, _):
        with self.lock:
            if self.law is None:
                return GetMemoryResponse(True, "not configured (no memory)", "", [])
            m = self.law.memory()
            return GetMemoryResponse(True, "%d numbers" % len(m), self.law.name, m)

    def on_set_memory(self, rq):
        with self.lock:
            if self.law is None or not self.claimed:
                return SetMemoryResponse(False, "memory: the rate controller is not running (configure and enable it "
                                                "first)")
            try:
                self.law.restore(list(rq.memory))
            except ValueError as e:
                return SetMemoryResponse(False, str(e))
            return SetMemoryResponse(True, "restored %d numbers" % len(rq.memory))

    def on_configure(self, rq):
        with self.lock:
            if self.claimed:
                return ConfigureRateResponse(False, "strategy: refused while enabled (disable first)")
            if rq.strategy not in ("fixed", "predicted", "adaptive"):
                return ConfigureRateResponse(False, "strategy: unknown '%s'; allowed: fixed, predicted, adaptive"
                                             % rq.strategy)
            if rq.axis > 2:
                return ConfigureRateResponse(False, "axis: must be 0, 1 or 2")
            if not finite_positive(rq.t0):
                return ConfigureRateResponse(False, "t0: must be finite and > 0")
            if not finite_positive(rq.quasi_static_threshold):
                return ConfigureRateResponse(False, "quasi_static_threshold: must be finite and > 0")
            if not finite_positive(rq.rate0):
                return ConfigureRateResponse(False, "rate0: must be finite and > 0")
            if rq.strategy == "adaptive":
                bad = check_adaptive(rq)
                if bad:
                    return ConfigureRateResponse(False, bad)
                self.law = AdaptiveRate(rq)
            else:
                self.law = HeldRate(rq.strategy, rq.rate0)
            self.axis, self.t0, self.threshold = rq.axis, rq.t0, rq.quasi_static_threshold
            return ConfigureRateResponse(True, "%s on axis %d, first eps' %g" % (self.law.name, self.axis,
                                                                                self.law.rate * self.t0))

    def on_enable(self, _):
        with self.lock:
            if self.law is None:
                return TriggerResponse(False, "not configured (call ~configure first)")
            if self.claimed:
                return TriggerResponse(True, "already enabled")
            try:
                r, _ = call_idempotent(self.claim, owner=self.owner, axes=[self.axis])
            except (rospy.ServiceException, rospy.ROSException) as e:
                return TriggerResponse(False, "claim_axes: dem_node does not answer (%s)" % e)
            if not r.success:
                return TriggerResponse(False, "claim_axes refused: " + r.message)
            self.claim_tick, self.claimed = r.tick, True
            rospy.loginfo("%s: '%s' %s controls axis %d from tick %d", NODE, self.owner, self.law.name, self.axis,
                          r.tick + 1)
            return TriggerResponse(True, "enabled")

    def on_disable(self, _):
        with self.lock:
            held, self.claimed = self.claimed, False
            _, why = release_axes(self.release_srv, self.owner, [self.axis], held)
            self.law = None
            return TriggerResponse(not why, why or "disabled; axis released")

    def on_index(self, msg):
        with self.lock:
            if not self.claimed or self.law is None or msg.tick <= self.claim_tick:
                return
            try:
                rate = self.law.update(msg.moment_index, self.threshold)
            except ValueError as e:
                rospy.logerr_throttle(1.0, "%s: tick %d: no command: %s" % (NODE, msg.tick, e))
                return
            self.cmd_pub.publish(CellCommand(header=msg.header, tick=msg.tick, owner=self.owner, axes=[self.axis],
                                             strain_rate=[rate]))
            self.state_pub.publish(RateState(header=msg.header, tick=msg.tick, strategy=self.law.name,
                                             axis=self.axis, moment_index=msg.moment_index, strain_rate=rate,
                                             strain_rate_dimensionless=rate * self.t0))


def main():
    rospy.init_node("rate_controller")  # the launch file's name= overrides it
    PyRateController()
    rospy.spin()


if __name__ == "__main__":
    main()
