"""Rotation matrices in sympy (the derivations' building blocks): about z, y and x, and in the plane."""

from __future__ import annotations

import sympy as sp


def rot2(angle) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def rotz3(angle) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle), 0], [sp.sin(angle), sp.cos(angle), 0], [0, 0, 1]])


def roty3(angle) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), 0, sp.sin(angle)], [0, 1, 0], [-sp.sin(angle), 0, sp.cos(angle)]])


def rotx3(angle) -> sp.Matrix:
    return sp.Matrix([[1, 0, 0], [0, sp.cos(angle), -sp.sin(angle)], [0, sp.sin(angle), sp.cos(angle)]])
