"""Each taught pose's joints per target: from the configuration the cell gives, else nearest the home joints."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from codegen.robot.config import FORMS

JOINTS_MATCH_DEG = 1.0  # taught joints must name a solution of the taught pose within this, per axis


class ReachError(Exception):
    """A taught pose the arm cannot take as the cell says; the message names station, pose and target."""


@dataclass(frozen=True)
class ArmPose:
    name: str
    motion: str  # "joint" or "linear"
    tcp2base: np.ndarray  # at calibration
    joints: np.ndarray  # deg, the taught configuration
    branch: int  # which analytic solution (the arm's configuration; codegen/robot/solve.py)


def configuration(form: str, arm, joints: np.ndarray) -> tuple:
    """What the program writes for these joints in the target's form (codegen/robot/config.py)."""
    return FORMS[form].of(arm, joints)


def select(form: str, arm, solutions: np.ndarray, value) -> tuple[np.ndarray, np.ndarray]:
    """The solution a configuration names, by the controller's rule: (joints, branch)."""
    return FORMS[form].select(arm, solutions, value)
