"""Simulated devices beside the controller (vision PC, camera, gripper, belt, sensors), above the dialects."""
