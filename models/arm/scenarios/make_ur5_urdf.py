#!/usr/bin/env python3
"""Writes ur5.urdf: a UR5-like arm from Universal Robots' published DH parameters (classic:
d1 0.089159, a2 -0.425, a3 -0.39225, d4 0.10915, d5 0.09465, d6 0.0823, alpha pi/2 0 0 pi/2 -pi/2 0),
written as modified DH so that each URDF link frame is the DH frame after its joint: joint k's
origin is Rx(alpha_{k-1}) Tx(a_{k-1}) Tz(d_k) and it turns about z. Collision shapes are placed in
the world at the zero pose (straight out along -x) and moved into their link frames here.
Run: python3 make_ur5_urdf.py > ur5.urdf (needs numpy)."""
import numpy as np

pi = np.pi
# modified DH, joint k: a_{k-1}, alpha_{k-1}, d_k
A = [0, 0, -0.425, -0.39225, 0, 0]
AL = [0, pi / 2, 0, 0, pi / 2, -pi / 2]
D = [0.089159, 0, 0, 0.10915, 0.09465, 0.0823]
LIM = 2 * pi
TOOL = 0.01  # tool0 on the flange, along z of the last joint frame
LINKS = ["base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link", "wrist_2_link", "wrist_3_link", "tool0"]
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint", "wrist_3_joint"]


def rx(a):
    c, s = np.cos(a), np.sin(a)
    t = np.eye(4)
    t[1:3, 1:3] = [[c, -s], [s, c]]
    return t


def tr(x, y, z):
    t = np.eye(4)
    t[:3, 3] = [x, y, z]
    return t


frames = [np.eye(4)]
for k in range(6):
    frames.append(frames[-1] @ rx(AL[k]) @ tr(A[k], 0, 0) @ tr(0, 0, D[k]))
frames.append(frames[-1] @ tr(0, 0, TOOL))

# world segments at the zero pose: (body, a, b, radius); cylinders (capsules once read)
Y0 = -0.136  # the upper arm's offset from the base axis (UR5 shoulder)
Y1 = -0.016  # the forearm's
W = frames[4][:3, 3]
CYL = [
    (0, (0, 0, 0.0), (0, 0, 0.06), 0.075),
    (1, (0, 0.01, 0.089159), (0, Y0, 0.089159), 0.06),
    (2, (-0.06, Y0, 0.089159), (-0.37, Y0, 0.089159), 0.05),
    (3, (-0.425, Y1 - 0.03, 0.089159), (-0.425, Y1, 0.089159), 0.055),
    (3, (-0.48, Y1, 0.089159), (-0.76, Y1, 0.089159), 0.04),
    (4, (W[0], -0.06, W[2]), (W[0], W[1] - 0.01, W[2]), 0.045),
    (5, (W[0], W[1], W[2] - 0.03), (W[0], W[1], W[2] - 0.11), 0.045),
    (6, (W[0], -0.14, W[2] - 0.0946), (W[0], -0.18, W[2] - 0.0946), 0.04),
]


def rpy_of(r):
    # R = Rz(yaw) Ry(pitch) Rx(roll)
    pitch = np.arcsin(-np.clip(r[2, 0], -1, 1))
    roll = np.arctan2(r[2, 1], r[2, 2])
    yaw = np.arctan2(r[1, 0], r[0, 0])
    return roll, pitch, yaw


def z_to(d):
    z = d / np.linalg.norm(d)
    x = np.cross([0, 1, 0], z) if abs(z[1]) < 0.9 else np.cross([1, 0, 0], z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def f(v):
    return " ".join(f"{x:.17g}" if abs(x) > 1e-12 else "0" for x in v)


out = ['<?xml version="1.0"?>',
       "<!-- A UR5-like arm (Universal Robots' DH parameters, approximate collision cylinders).",
       "     Written by make_ur5_urdf.py: edit that, not this. -->",
       '<robot name="ur5">']
for b, name in enumerate(LINKS):
    out.append(f'  <link name="{name}">')
    inv = np.linalg.inv(frames[b])
    for body, a, c, r in CYL:
        if body != b:
            continue
        a, c = (inv @ np.array([*a, 1.0]))[:3], (inv @ np.array([*c, 1.0]))[:3]
        mid, d = 0.5 * (a + c), c - a
        out.append(f'    <collision><origin xyz="{f(mid)}" rpy="{f(rpy_of(z_to(d)))}"/>'
                   f'<geometry><cylinder radius="{r}" length="{np.linalg.norm(d):.9g}"/></geometry></collision>')
    if name == "tool0":  # a gripper: a box on the flange
        out.append('    <collision><origin xyz="0 0 0.05" rpy="0 0 0"/><geometry><box size="0.05 0.08 0.1"/></geometry></collision>')
    out.append("  </link>")
for k, j in enumerate(JOINTS):
    xyz = (A[k], -np.sin(AL[k]) * D[k], np.cos(AL[k]) * D[k])
    out.append(f'  <joint name="{j}" type="revolute"><parent link="{LINKS[k]}"/><child link="{LINKS[k + 1]}"/>'
               f'<origin xyz="{f(xyz)}" rpy="{f((AL[k], 0, 0))}"/><axis xyz="0 0 1"/>'
               f'<limit lower="{-LIM:.9g}" upper="{LIM:.9g}" effort="150" velocity="3.15"/></joint>')
out.append(f'  <joint name="tool0_fixed_joint" type="fixed"><parent link="wrist_3_link"/><child link="tool0"/>'
           f'<origin xyz="0 0 {TOOL}" rpy="0 0 0"/></joint>')
out.append("</robot>")
print("\n".join(out))
