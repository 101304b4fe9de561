"""The rest of URScript's standard environment: installation settings a program repeats (accepted, no effect
modelled), flags, and the built-ins of the manual's script directory this interpreter refuses, with why."""

# PolyScope writes the installation's settings at the top of every program it exports (the socket form starts
# with them too): analog input domains, tool voltage and communication, input actions, gravity, the safety
# mode's transition hardness, the TCP and the payload. The TCP and payload are modelled (motion.py); the
# others change nothing a trace shows here (no analog sensor, no tool communication, no gravity model), so
# they are accepted and their arguments checked for count only. set_flag(n, b) / get_flag(n): the 32 flags
# 0..31 (URScript manual, module interfaces), modelled as booleans of the run.

from __future__ import annotations

from codegen.dialects.core.values import RunError, show

# installation settings: name -> (fewest, most) arguments (positional and named together)
SETTINGS = {
    "set_standard_analog_input_domain": (2, 2),
    "set_tool_analog_input_domain": (2, 2),
    "set_analog_outputdomain": (2, 2),
    "set_analog_inputrange": (2, 2),
    "set_tool_voltage": (1, 1),
    "set_input_actions_to_default": (0, 0),
    "set_gravity": (1, 1),
    "set_safety_mode_transition_hardness": (1, 1),
    "set_tool_communication": (1, 6),
    "set_tool_output_mode": (1, 1),
    "set_tool_digital_output_mode": (2, 2),
    "set_standard_digital_input_action": (2, 3),
    "set_configurable_digital_input_action": (2, 3),
    "set_tool_digital_input_action": (2, 3),
    "set_runstate_standard_digital_output_to_value": (2, 2),
    "set_runstate_configurable_digital_output_to_value": (2, 2),
    "set_runstate_tool_digital_output_to_value": (2, 2),
    "set_runstate_standard_analog_output_to_value": (2, 2),
    "set_tool_analog_io_work_mode": (1, 1),
    "set_tool_digital_io_work_mode": (1, 1),
    "set_tool_analog_output_domain": (1, 2),
    "set_tool_digital_io_config": (1, 4),
    "zero_ftsensor": (0, 0),
    "rtde_set_watchdog": (2, 3),
    "tool_wrench_limit_disable": (0, 0),
    "motion_version_set": (1, 1),
    "set_runstate_standard_digital_outputs": (1, 1),
    "set_runstate_configurable_digital_outputs": (1, 1),
    "set_runstate_tool_digital_outputs": (1, 1),
    "set_runstate_outputs": (1, 1),
}
FLAG_MAX = 31
UNDEFINED = "is not defined: not a function of the program nor a built-in modelled here"

# Built-ins of the URScript manual's script directory that this interpreter does not model, and why; a
# program that calls one is refused when it is loaded, naming the call's file:line.
NOT_MODELLED = {
    **dict.fromkeys(
        ("force_mode", "end_force_mode", "force_mode_set_damping", "force_mode_set_gain_scaling", "force_mode_example"),
        "force control needs the contact forces of a real process",
    ),
    **dict.fromkeys(("freedrive_mode", "end_freedrive_mode", "teach_mode", "end_teach_mode"), "hand guiding"),
    **dict.fromkeys(
        (
            "path_offset_enable",
            "path_offset_disable",
            "path_offset_set",
            "path_offset_get",
            "path_offset_set_alpha_filter",
            "path_offset_set_max_offset",
        ),
        "path offsets change a move while it runs (the trace has each move's commanded pose only)",
    ),
    **dict.fromkeys(
        (
            "socket_open",
            "socket_close",
            "socket_send_string",
            "socket_send_line",
            "socket_send_byte",
            "socket_send_int",
            "socket_read_string",
            "socket_read_line",
            "socket_read_byte_list",
            "socket_read_ascii_float",
            "socket_read_binary_integer",
            "socket_get_var",
            "socket_set_var",
            "rpc_factory",
            "http_get",
            "http_post",
        ),
        "network peers are not simulated (use registers, which the run's devices answer)",
    ),
    **dict.fromkeys(
        (
            "modbus_add_signal",
            "modbus_delete_signal",
            "modbus_get_signal_status",
            "modbus_send_custom_command",
            "modbus_set_digital_input_action",
            "modbus_set_output_register",
            "modbus_set_output_signal",
            "modbus_set_runstate_dependent_choice",
            "modbus_set_signal_update_frequency",
        ),
        "Modbus devices are not simulated",
    ),
    **dict.fromkeys(
        ("conveyor_pulse_decode", "get_conveyor_tick_count", "set_conveyor_tick_count", "track_conveyor_circular"),
        "only encoder_* with track_conveyor_linear is modelled",
    ),
    **dict.fromkeys(
        ("mc_initialize", "mc_add_linear", "mc_add_circular", "mc_add_path", "mc_load_path", "mc_run_motion"),
        "the remote-TCP motion functions are not modelled",
    ),
    # The arm's dynamics and torque control (URScript manual SW 5.25, direct_torque: "Direct Joint Torque Control
    # ... Sets the target torque for all robot joints at 500Hz"; torque_command is its name in the 5.22 beta; the
    # other names as public programs call them, their pages not read here: unconfirmed).
    **dict.fromkeys(
        (
            "direct_torque",
            "torque_command",
            "get_mass_matrix",
            "get_coriolis_and_centrifugal_torques",
            "get_jacobian",
            "get_jacobian_time_derivative",
            "get_target_joint_accelerations",
        ),
        "the arm's dynamics (mass matrix, Jacobian, joint torques) are not simulated",
    ),
    # The world model of frames (PolyScope 5.21 and later, PolyScope X: names as the programs PolyScope X
    # writes call them; the manual's pages not read here: unconfirmed).
    **dict.fromkeys(
        (
            "reset_world_model",
            "add_frame",
            "delete_frame",
            "move_frame",
            "get_pose",
            "get_frame_parent",
            "attach_frame",
            "convert_pose",
        ),
        "the installation's world model of frames (poses here are in the base frame)",
    ),
    "get_rtde_value": "the controller's RTDE outputs are not simulated",
    "servoc": "a servo move in tool space is not modelled (servoj is)",
    "inv": "matrix algebra is not modelled (element-wise arithmetic of arrays is)",
    "transpose": "matrix algebra is not modelled (element-wise arithmetic of arrays is)",
    "time": "the wall clock is not simulated (the program's clock is its moves, sleeps and waits)",
    "tool_contact_direction": "contact detection needs the forces of a real process",
    "pose_dist": "the manual gives no formula for its metric",
    "screw_driving": "screw driving needs a real tool",
    "get_joint_torques": "joint torques are not simulated",
    "get_joint_temp": "temperatures are not simulated",
    "get_controller_temp": "temperatures are not simulated",
    "position_deviation_warning": "position deviations are not simulated",
    "set_pos": "the simulated arm is moved by motion commands only",
    "powerdown": "stopping the controller is not modelled",
    "protective_stop": "a protective stop is not modelled (halt ends the program)",
}


def builtins() -> dict:
    table = {}
    for name, (fewest, most) in SETTINGS.items():

        def setting(fr, args, kwargs, where, name=name, fewest=fewest, most=most):
            given = len(args) + len(kwargs)
            if not fewest <= given <= most:
                count = str(fewest) if fewest == most else f"{fewest} to {most}"
                raise RunError(f"{where}: {name} takes {count} arguments, got {given}")
            fr.m.state.settings[name] = (tuple(args), dict(kwargs))

        table[name] = setting

    def flag(value, where: str, what: str) -> int:
        if type(value) is not int or not 0 <= value <= FLAG_MAX:
            raise RunError(f"{where}: {what} takes a flag number 0..{FLAG_MAX}, got {show(value)}")
        return value

    def set_flag(fr, args, kwargs, where):
        if len(args) != 2 or not isinstance(args[1], bool):
            raise RunError(f"{where}: set_flag(n, b) takes a flag number and True or False")
        fr.m.state.flags[flag(args[0], where, "set_flag")] = args[1]

    def get_flag(fr, args, kwargs, where):
        if len(args) != 1:
            raise RunError(f"{where}: get_flag(n) takes a flag number")
        return bool(fr.m.state.flags.get(flag(args[0], where, "get_flag"), False))

    table["set_flag"] = set_flag
    table["get_flag"] = get_flag
    return table
