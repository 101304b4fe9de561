"""The arm: catalogue, kinematics, vendor configuration, tool."""
