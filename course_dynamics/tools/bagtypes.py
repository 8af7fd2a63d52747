"""The message types a bag is read with: ROS1 Noetic's or ROS2 Humble's, with franka_msgs' FrankaState and Errors.

A bag that carries its own definitions is read with those (:mod:`~course_dynamics.tools.bags`); these serve the bags
that do not (ROS2 bags recorded before Iron), and define the Franka messages, which no ROS distribution ships.
"""
from __future__ import annotations

from functools import lru_cache

JOINT_STATE, FRANKA_STATE, FRANKA_ERRORS = ("sensor_msgs/msg/JointState", "franka_msgs/msg/FrankaState",
                                            "franka_msgs/msg/Errors")

# franka_msgs/msg/FrankaState and Errors as franka_ros 0.10 defines them (frankaemika/franka_ros, franka_msgs/msg),
# field for field in their order, one (type, names) group per run of fields of one type. Only header, q, dq and tau_J
# are read, but the whole message is needed: a message is decoded field after field, its length is checked, and the
# ROS1 MD5 sum covers every field and constant (the test checks ours against rosserial's from franka_ros 0.10).
#: franka_msgs/msg/FrankaState as franka_ros 0.10 defines it, as (type, space-separated names) groups in order.
FRANKA_STATE_FIELDS = (
    ("std_msgs/Header", "header"), ("float64[6]", "cartesian_collision cartesian_contact"),
    ("float64[7]", "q q_d dq dq_d ddq_d theta dtheta tau_J dtau_J tau_J_d"), ("float64[6]", "K_F_ext_hat_K"),
    ("float64[2]", "elbow elbow_d elbow_c delbow_c ddelbow_c"), ("float64[7]", "joint_collision joint_contact"),
    ("float64[6]", "O_F_ext_hat_K O_dP_EE_d"), ("float64[3]", "O_ddP_O"), ("float64[6]", "O_dP_EE_c O_ddP_EE_c"),
    ("float64[7]", "tau_ext_hat_filtered"), ("float64", "m_ee"), ("float64[3]", "F_x_Cee"), ("float64[9]", "I_ee"),
    ("float64", "m_load"), ("float64[3]", "F_x_Cload"), ("float64[9]", "I_load"), ("float64", "m_total"),
    ("float64[3]", "F_x_Ctotal"), ("float64[9]", "I_total"),
    ("float64[16]", "O_T_EE O_T_EE_d O_T_EE_c F_T_EE F_T_NE NE_T_EE EE_T_K"),
    ("float64", "time control_command_success_rate"),
    ("uint8", "ROBOT_MODE_OTHER=0 ROBOT_MODE_IDLE=1 ROBOT_MODE_MOVE=2 ROBOT_MODE_GUIDING=3 ROBOT_MODE_REFLEX=4 "
              "ROBOT_MODE_USER_STOPPED=5 ROBOT_MODE_AUTOMATIC_ERROR_RECOVERY=6 robot_mode"),
    ("franka_msgs/Errors", "current_errors last_motion_errors"),
)
#: franka_msgs/msg/Errors as franka_ros 0.10 defines it, as (type, space-separated names) groups in order.
FRANKA_ERRORS_FIELDS = (("bool", """joint_position_limits_violation cartesian_position_limits_violation
    self_collision_avoidance_violation joint_velocity_violation cartesian_velocity_violation
    force_control_safety_violation joint_reflex cartesian_reflex max_goal_pose_deviation_violation
    max_path_pose_deviation_violation cartesian_velocity_profile_safety_violation
    joint_position_motion_generator_start_pose_invalid joint_motion_generator_position_limits_violation
    joint_motion_generator_velocity_limits_violation joint_motion_generator_velocity_discontinuity
    joint_motion_generator_acceleration_discontinuity cartesian_position_motion_generator_start_pose_invalid
    cartesian_motion_generator_elbow_limit_violation cartesian_motion_generator_velocity_limits_violation
    cartesian_motion_generator_velocity_discontinuity cartesian_motion_generator_acceleration_discontinuity
    cartesian_motion_generator_elbow_sign_inconsistent cartesian_motion_generator_start_elbow_invalid
    cartesian_motion_generator_joint_position_limits_violation
    cartesian_motion_generator_joint_velocity_limits_violation cartesian_motion_generator_joint_velocity_discontinuity
    cartesian_motion_generator_joint_acceleration_discontinuity cartesian_position_motion_generator_invalid_frame
    force_controller_desired_force_tolerance_violation controller_torque_discontinuity start_elbow_sign_inconsistent
    communication_constraints_violation power_limit_violation joint_p2p_insufficient_torque_for_planning
    tau_j_range_violation instability_detected joint_move_in_wrong_direction
    cartesian_spline_motion_generator_violation joint_via_motion_generator_planning_joint_limit_violation
    base_acceleration_initialization_timeout base_acceleration_invalid_reading"""),)


def _msg_text(fields) -> str:
    """The ``.msg`` text of (type, space-separated names) groups: one ``type name`` line per name."""
    return "".join(f"{kind} {name}\n" for kind, names in fields for name in names.split())


@lru_cache(maxsize=2)
def typestore(ros1: bool):
    """The message types of ROS1 Noetic (``ros1``) or ROS2 Humble, with franka_msgs' FrankaState and Errors.

    Parameters
    ----------
    ros1 : bool
        ROS1 Noetic's types if true, else ROS2 Humble's.

    Returns
    -------
    rosbags.typesys.store.Typestore
        rosbags' store of the types, with the Franka messages registered; one per distribution.
    """
    # rosbags is imported where it is used: it takes 0.1 s, which every other command would pay at start-up.
    from rosbags.typesys import Stores, get_types_from_msg, get_typestore

    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    store.register({**get_types_from_msg(_msg_text(FRANKA_ERRORS_FIELDS), FRANKA_ERRORS),
                    **get_types_from_msg(_msg_text(FRANKA_STATE_FIELDS), FRANKA_STATE)})
    return store


__all__ = ["FRANKA_ERRORS_FIELDS", "FRANKA_STATE_FIELDS", "typestore"]
