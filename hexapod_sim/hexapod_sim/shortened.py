# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
A shortened tibia (damage kind ``shortened``): the geometry every engine gives it (ROS-free).

The tibia is cut so that its tip is at ``fraction`` of its length from the knee: the foot sphere
moves in, the shank's box is cut where the foot now is, and the mass and its centre scale with
the length. One home for the arithmetic: MuJoCo applies it to its compiled model, DART to its
shape nodes, PyBullet to the URDF it loads.
"""

from __future__ import annotations

from dataclasses import dataclass
import xml.etree.ElementTree as ET


@dataclass(frozen=True)
class TibiaShape:
    """A tibia along its link's x axis: the shank box [box_lo, box_hi], the foot sphere, mass."""

    box_lo: float
    box_hi: float
    foot_x: float
    foot_radius: float
    mass: float
    com_x: float

    @property
    def length(self) -> float:
        """From the knee to the tip of the foot [m]."""
        return self.foot_x + self.foot_radius

    def shortened(self, fraction: float) -> TibiaShape:
        """Return the tibia cut to ``fraction`` (0..1] of its length."""
        foot_x = fraction * self.length - self.foot_radius
        return TibiaShape(
            box_lo=self.box_lo,
            box_hi=max(min(self.box_hi, foot_x), self.box_lo + 1e-3),
            foot_x=foot_x,
            foot_radius=self.foot_radius,
            mass=self.mass * fraction,
            com_x=self.com_x * fraction,
        )


def _xyz(element: ET.Element) -> list[float]:
    origin = element.find('origin')
    return [
        float(v) for v in (origin.get('xyz', '0 0 0') if origin is not None else '0 0 0').split()
    ]


def _set_xyz(element: ET.Element, xyz: list[float]) -> None:
    origin = element.find('origin')
    if origin is None:
        origin = ET.SubElement(element, 'origin')
    origin.set('xyz', ' '.join(f'{v:.6g}' for v in xyz))


def tibia_shape(link: ET.Element) -> TibiaShape:
    """Read a tibia link of the URDF (a box collision and a sphere collision)."""
    box = sphere = None
    for collision in link.findall('collision'):
        geometry = collision.find('geometry')
        if geometry is not None and geometry.find('box') is not None:
            box = collision
        elif geometry is not None and geometry.find('sphere') is not None:
            sphere = collision
    if box is None or sphere is None:
        raise ValueError(f'tibia {link.get("name")} has no box and sphere collision to shorten')
    length = float(box.find('geometry/box').get('size').split()[0])
    centre = _xyz(box)[0]
    inertial = link.find('inertial')
    return TibiaShape(
        box_lo=centre - length / 2,
        box_hi=centre + length / 2,
        foot_x=_xyz(sphere)[0],
        foot_radius=float(sphere.find('geometry/sphere').get('radius')),
        mass=float(inertial.find('mass').get('value')),
        com_x=_xyz(inertial)[0],
    )


def shortened_urdf(urdf_text: str, fractions: dict[int, float]) -> str:
    """Return the URDF with each leg of ``fractions`` (leg -> fraction kept) shortened."""
    root = ET.fromstring(urdf_text)
    for leg, fraction in fractions.items():
        link = root.find(f"link[@name='link_{leg}_3']")
        if link is None:
            raise ValueError(f'the URDF has no tibia link_{leg}_3')
        new = tibia_shape(link).shortened(fraction)
        inertial = link.find('inertial')
        inertial.find('mass').set('value', f'{new.mass:.6g}')
        com = _xyz(inertial)
        _set_xyz(inertial, [new.com_x, com[1], com[2]])
        inertia = inertial.find('inertia')
        for key in ('ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz'):
            inertia.set(key, f'{float(inertia.get(key)) * fraction:.6g}')
        for collision in link.findall('collision'):
            geometry = collision.find('geometry')
            xyz = _xyz(collision)
            if geometry.find('box') is not None:
                box = geometry.find('box')
                size = box.get('size').split()
                size[0] = f'{new.box_hi - new.box_lo:.6g}'
                box.set('size', ' '.join(size))
                _set_xyz(collision, [(new.box_hi + new.box_lo) / 2, xyz[1], xyz[2]])
            else:
                _set_xyz(collision, [new.foot_x, xyz[1], xyz[2]])
    return ET.tostring(root, encoding='unicode')
