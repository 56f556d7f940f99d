"""rig_service_calls.py: dem_node's services called from the Python
controllers (py_servo_controller.py, py_rate_controller.py) the way the C++
ones call them (include/virtual_triaxial/ros/idempotent_call.h).

The answer to a ROS 1 service call can be lost after the server ran the
request (ros/ros_comm#1976); a request whose repetition changes nothing
(get_info, claim_axes: a repeated claim answers the first claim's tick,
axis_arbiter.h) is then simply made again.
"""
import time

import rospy

ATTEMPTS = 3     # calls in all
PAUSE = 0.05     # wall seconds before each repeated call

# The words of rig answers that another node acts on: the same as
# include/virtual_triaxial/ros/rig_reply_words.h (checked equal by
# tests/rostest/unit_rig_reply_words.cpp).
OWNER_REFUSAL = "owner:"             # AxisArbiter refusals about the caller
NOT_CLAIMED_YET = "not claimed yet"  # a servo's ~enable answer, claim pending


def enabled_not_claimed_yet(why):
    """A servo's ~enable answer while its claim is pending (as
    reply_words::enabled_not_claimed_yet)."""
    return "enabled; %s (%s), retrying" % (NOT_CLAIMED_YET, why)


def call_idempotent(proxy, **request):
    """(answer, calls): the first answered call's answer and how many calls
    were made; raises the last call's exception when none was answered."""
    for k in range(ATTEMPTS):
        if k > 0:
            time.sleep(PAUSE)
        try:
            return proxy(**request), k + 1
        except (rospy.ServiceException, rospy.ROSException):
            if k == ATTEMPTS - 1:
                raise
    raise AssertionError("unreachable")


def release_axes(proxy, owner, axes, held):
    """(answered, why): release_axes for `owner`, asked even when it `held`
    no claim (dem_node may list one whose answer was lost). `why` is '' when
    the axes are released, or when nothing was held (a refusal or silence
    then means none, as the caller thinks); a repeated call refused as the
    request of an owner of no axis (the refusal names the field "owner")
    means the lost call released them (as ReleaseAnswer::why in
    include/virtual_triaxial/ros/idempotent_call.h)."""
    try:
        r, calls = call_idempotent(proxy, owner=owner, axes=list(axes))
    except (rospy.ServiceException, rospy.ROSException):
        return False, "release_axes: dem_node does not answer" if held else ""
    if r.success or (calls > 1 and r.message.startswith(OWNER_REFUSAL)) or not held:
        return True, ""
    return True, "release_axes refused: " + r.message
