# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Fill any ROS message with deterministic pseudo-random values (for round-trip tests)."""

from __future__ import annotations

import random
import re
import zlib

import numpy as np

_INT_RANGES = {
    'int8': (-128, 127),
    'uint8': (0, 255),
    'int16': (-(2**15), 2**15 - 1),
    'uint16': (0, 2**16 - 1),
    'int32': (-(2**31), 2**31 - 1),
    'uint32': (0, 2**32 - 1),
    'int64': (-(2**63), 2**63 - 1),
    'uint64': (0, 2**64 - 1),
    'byte': (0, 255),
    'char': (0, 255),
    'octet': (0, 255),
}


def _scalar(kind: str, rng: random.Random):
    if kind in ('float', 'double', 'float32', 'float64'):
        return (
            float(np.float32(rng.uniform(-1e3, 1e3)))
            if kind in ('float', 'float32')
            else rng.uniform(-1e6, 1e6)
        )
    if kind == 'boolean':
        return rng.random() < 0.5
    if kind == 'string' or kind.startswith('string<'):
        return ''.join(rng.choice('abcxyz_ 0123456789') for _ in range(rng.randint(0, 12)))
    if kind in _INT_RANGES:
        lo, hi = _INT_RANGES[kind]
        value = rng.randint(lo, hi)
        return bytes([value]) if kind == 'byte' else value
    raise KeyError(kind)


def request_seed(msg) -> int:
    """
    A seed from a message's field values.

    (Not from its CDR bytes: the alignment padding between fields need not be zero, so two
    processes can serialise equal messages differently.)
    """
    return zlib.crc32(repr(msg).encode())


def fill(msg_type, seed: int):
    """An instance of msg_type with every field set from a generator seeded by seed."""
    rng = random.Random(seed)
    return _fill(msg_type, rng)


def _fill(msg_type, rng: random.Random):
    msg = msg_type()
    for name, kind in msg_type.get_fields_and_field_types().items():
        if kind == 'uint32' and name == 'nanosec':
            # a valid builtin_interfaces/Time: nanosec < 1e9
            setattr(msg, name, rng.randint(0, 999_999_999))
            continue
        setattr(msg, name, _value(kind, getattr(msg, name), rng))
    return msg


def _value(kind: str, current, rng: random.Random):
    m = re.fullmatch(r'sequence<(.+?)(?:, \d+)?>', kind)
    array = re.fullmatch(r'(.+)\[(\d+)\]', kind)
    if m or array:
        inner = (m or array).group(1)
        n = int(array.group(2)) if array else rng.randint(0, 5)
        values = [_value(inner, None, rng) for _ in range(n)]
        if isinstance(current, np.ndarray):
            return np.array(values, dtype=current.dtype)
        return values
    try:
        return _scalar(kind, rng)
    except KeyError:
        pkg, name = kind.split('/')
        module = __import__(f'{pkg}.msg', fromlist=[name])
        return _fill(getattr(module, name), rng)
