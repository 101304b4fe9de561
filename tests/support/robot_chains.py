"""Independent arm models for the tests only: ikpy chains built from the vendors' joint origins and axes."""

from __future__ import annotations

import math
import warnings

import ikpy.chain
import ikpy.link
import numpy as np

HALF_PI = math.pi / 2
# (name, origin xyz mm, origin rpy rad, joint axis or None for fixed), joint origins as in the vendors' models
VENDOR_CHAINS = {
    # ros-industrial kuka_experimental kuka_kr6_support/urdf/kr6r700sixx_macro.xacro; tool0 = KRC's flange frame
    "KR 6 R700 sixx": [
        ("a1", (0, 0, 400), (0, 0, 0), (0, 0, -1)),
        ("a2", (25, 0, 0), (0, 0, 0), (0, 1, 0)),
        ("a3", (315, 0, 0), (0, 0, 0), (0, 1, 0)),
        ("a4", (0, 0, 35), (0, 0, 0), (-1, 0, 0)),
        ("a5", (365, 0, 0), (0, 0, 0), (0, 1, 0)),
        ("a6", (80, 0, 0), (0, 0, 0), (-1, 0, 0)),
        ("tool0", (0, 0, 0), (0, HALF_PI, 0), None),
    ],
    # ros-industrial abb abb_irb2400_support/urdf/irb2400_macro.xacro; tool0 (z out of the flange) as in
    # abb_experimental's newer models (joint_6-tool0 rpy 0 pi/2 0)
    "IRB 2400/10": [
        ("j1", (0, 0, 0), (0, 0, 0), (0, 0, 1)),
        ("j2", (100, 0, 615), (0, 0, 0), (0, 1, 0)),
        ("j3", (0, 0, 705), (0, 0, 0), (0, 1, 0)),
        ("j4", (258, 0, 135), (0, 0, 0), (1, 0, 0)),
        ("j5", (497, 0, 0), (0, 0, 0), (0, 1, 0)),
        ("j6", (85, 0, 0), (0, 0, 0), (1, 0, 0)),
        ("tool0", (0, 0, 0), (0, HALF_PI, 0), None),
    ],
}


def ur_chain(d1: float, a2: float, a3: float, d4: float, d5: float, d6: float) -> list:
    """UniversalRobots/Universal_Robots_ROS2_Description urdf/ur_macro.xacro with the joint origins of
    config/<model>/default_kinematics.yaml, from the controller's 'base' (base_link turned pi about z)."""
    return [
        ("base->base_link", (0, 0, 0), (0, 0, -math.pi), None),
        ("base_link->base_link_inertia", (0, 0, 0), (0, 0, math.pi), None),
        ("shoulder_pan", (0, 0, d1), (0, 0, 0), (0, 0, 1)),
        ("shoulder_lift", (0, 0, 0), (HALF_PI, 0, 0), (0, 0, 1)),
        ("elbow", (a2, 0, 0), (0, 0, 0), (0, 0, 1)),
        ("wrist_1", (a3, 0, d4), (0, 0, 0), (0, 0, 1)),
        ("wrist_2", (0, -d5, 0), (HALF_PI, 0, 0), (0, 0, 1)),
        ("wrist_3", (0, d6, 0), (HALF_PI, math.pi, math.pi), (0, 0, 1)),
        ("flange", (0, 0, 0), (0, -HALF_PI, -HALF_PI), None),
        ("tool0", (0, 0, 0), (HALF_PI, 0, HALF_PI), None),
    ]


VENDOR_CHAINS["UR5e"] = ur_chain(162.5, -425.0, -392.2, 133.3, 99.7, 99.6)
VENDOR_CHAINS["UR10e"] = ur_chain(180.7, -612.7, -571.55, 174.15, 119.85, 116.55)


def ikpy_chain(spec: list) -> tuple[ikpy.chain.Chain, np.ndarray]:
    links, active = [], []
    for name, xyz, rpy, axis in spec:
        kwargs = {"joint_type": "fixed"} if axis is None else {"rotation": np.array(axis, dtype=float)}
        links.append(
            ikpy.link.URDFLink(name, np.array(xyz, float), np.array(rpy, float), use_symbolic_matrix=False, **kwargs)
        )
        active.append(axis is not None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return ikpy.chain.Chain(links, active_links_mask=active), np.array(active)


# The catalogue's KUKA and ABB arms, from the ROS-Industrial support packages' joint origins (mm) and
# axes, which copy the vendors' data sheets; tool0: the flange frame, z out of the flange face.
_KUKA_AXES = [(0, 0, -1), (0, 1, 0), (0, 1, 0), (-1, 0, 0), (0, 1, 0), (-1, 0, 0)]
_ABB_AXES = [(0, 0, 1), (0, 1, 0), (0, 1, 0), (1, 0, 0), (0, 1, 0), (1, 0, 0)]
_ORIGINS = {
    "KR 6 R900 sixx": ("kuka", [(0, 0, 400), (25, 0, 0), (455, 0, 0), (0, 0, 35), (420, 0, 0), (80, 0, 0)]),
    "KR 10 R1100 sixx": ("kuka", [(0, 0, 400), (25, 0, 0), (560, 0, 0), (0, 0, 35), (515, 0, 0), (80, 0, 0)]),
    "KR 210 R2700 extra": ("kuka", [(0, 0, 675), (350, 0, 0), (1150, 0, 0), (0, 0, -41), (1200, 0, 0), (215, 0, 0)]),
    "IRB 140": ("abb", [(0, 0, 104), (70, 0, 248), (0, 0, 360), (380, 0, 0), (0, 0, 0), (65, 0, 0)]),
    "IRB 1200-5/0.9": ("abb", [(0, 0, 399.1), (0, 0, 0), (0, 0, 448), (0, 0, 42), (451, 0, 0), (82, 0, 0)]),
    "IRB 1600-10/1.45": ("abb", [(0, 0, 0), (150, 0, 486.5), (0, 0, 700), (300, 0, 0), (300, 0, 0), (65, 0, 0)]),
    "IRB 4600-60/2.05": ("abb", [(0, 0, 495), (175, 0, 0), (0, 0, 900), (0, 0, 175), (960, 0, 0), (135, 0, 0)]),
}
CATALOGUE_CHAINS = {
    model: [
        *(
            (f"joint_{i + 1}", xyz, (0, 0, 0), axis)
            for i, (xyz, axis) in enumerate(zip(origins, _KUKA_AXES if vendor == "kuka" else _ABB_AXES, strict=True))
        ),
        ("tool0", (0, 0, 0), (0, HALF_PI, 0), None),
    ]
    for model, (vendor, origins) in _ORIGINS.items()
}
CATALOGUE_CHAINS.update(
    {
        "UR3e": ur_chain(151.85, -243.55, -213.2, 131.05, 85.35, 92.1),
        "UR5e": VENDOR_CHAINS["UR5e"],
        "UR10e": VENDOR_CHAINS["UR10e"],
        "UR16e": ur_chain(180.7, -478.4, -360.0, 174.15, 119.85, 116.55),
        "UR20": ur_chain(236.3, -862.0, -728.7, 201.0, 159.3, 154.3),
    }
)


def chain_frames(model: str, joints_deg) -> list[np.ndarray]:
    """Every link frame (base frame, mm) of a catalogue arm at these axis values, from its ikpy chain."""
    chain, active = ikpy_chain(CATALOGUE_CHAINS[model])
    angles = np.zeros(len(active))
    angles[active] = np.radians(joints_deg)
    return chain.forward_kinematics(angles, full_kinematics=True)
