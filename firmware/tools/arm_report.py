#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Print the firmware module's figures for the STM32F407 as BENCH lines (make -C firmware arm).

Flash: the module's own code (its objects' text) and the probe linked as a firmware links it,
with the soft-float and libm routines it pulls in. RAM: the one Firmware instance (static, no
heap) and the deepest stack frame (-fstack-usage). With --counts, instruction counts of the
probe's scenarios on QEMU's Cortex-M4 board (one instruction per translation block, every block
logged), and the time they take at 168 MHz for a stated cycles-per-instruction range.
"""

from __future__ import annotations

import argparse
import glob
import os
import subprocess
import sys

CLOCK_HZ = 168e6
#: Cycles per instruction assumed for time estimates: 1.0 (every instruction one cycle) to 1.5
#: (flash wait states the ART accelerator does not hide, multi-cycle loads and branches).
CPI_RANGE = (1.0, 1.5)
MAX_ROWS = 1200  # a 10 s period at 120 Hz


def _size(tool: str, path: str) -> tuple[int, int, int]:
    out = subprocess.run([tool, path], capture_output=True, text=True, check=True).stdout
    text, data, bss = (int(v) for v in out.splitlines()[1].split()[:3])
    return text, data, bss


def _symbol_size(nm: str, elf: str, name: str) -> int:
    out = subprocess.run([nm, '-S', '-C', elf], capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        parts = line.split(maxsplit=3)
        if len(parts) == 4 and name in parts[3]:
            return int(parts[1], 16)
    raise SystemExit(f'{elf}: no symbol {name}')


def count_instructions(qemu: str, elf: str) -> int:
    """Run a probe on QEMU's netduinoplus2 (Cortex-M4) and count the instructions it executes."""
    cmd = [
        qemu,
        '-M',
        'netduinoplus2',
        '-nographic',
        '-semihosting-config',
        'enable=on,target=native',
        '-singlestep',
        '-d',
        'exec,nochain',
        '-D',
        '/dev/stdout',
        '-kernel',
        elf,
    ]
    count = 0
    with subprocess.Popen(cmd, stdout=subprocess.PIPE) as proc:
        for line in proc.stdout:
            if line.startswith(b'Trace'):
                count += 1
    if proc.returncode != 0:
        raise SystemExit(f'{qemu} failed on {elf} (exit status {proc.returncode})')
    return count


def _ms(instructions: float) -> str:
    lo, hi = (instructions * cpi / CLOCK_HZ * 1000.0 for cpi in CPI_RANGE)
    if hi < 1.0:
        return f'{lo * 1000:.0f}-{hi * 1000:.0f} us'
    return f'{lo:.0f}-{hi:.0f} ms'


def main(argv: list[str] | None = None) -> int:
    """Print the BENCH lines; with --counts also the instruction counts."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('objects', nargs='+', help="the module's ARM object files")
    parser.add_argument('--build', required=True, help='the build directory (probe*.elf)')
    parser.add_argument('--size', default='arm-none-eabi-size')
    parser.add_argument('--nm', default='arm-none-eabi-nm')
    parser.add_argument('--qemu', default='qemu-system-arm')
    parser.add_argument('--counts', action='store_true', help='count instructions on QEMU')
    args = parser.parse_args(argv)
    module_text = sum(_size(args.size, o)[0] for o in args.objects)
    module_static = sum(sum(_size(args.size, o)[1:]) for o in args.objects)
    probe = os.path.join(args.build, 'probe0.elf')
    linked_text, linked_data, _ = _size(args.size, probe)
    instance = _symbol_size(args.nm, probe, 'g_firmware')
    frames = []
    for su in glob.glob(os.path.join(args.build, '*.su')):
        for line in open(su):
            parts = line.rstrip('\n').split('\t')
            if len(parts) >= 2 and parts[1].isdigit():
                frames.append((int(parts[1]), parts[0].split(':')[-1]))
    deepest = max(frames)
    print(f'BENCH firmware_flash_module {module_text} bytes')
    print(f'BENCH firmware_flash_linked {linked_text + linked_data} bytes')
    print(f'BENCH firmware_ram_instance {instance} bytes')
    print(f'BENCH firmware_ram_module_static {module_static} bytes')
    print(f'BENCH firmware_stack_largest_frame {deepest[0]} bytes')
    print(
        f'# module text {module_text} B (static data {module_static} B); linked with soft-float'
        f' and libm: {linked_text + linked_data} B flash; one Firmware instance {instance} B of'
        f' RAM (the 1200-row table {MAX_ROWS * 18 * 4} B of it); largest stack frame'
        f' {deepest[0]} B ({deepest[1]})'
    )
    if not args.counts:
        return 0
    counts = {
        s: count_instructions(args.qemu, os.path.join(args.build, f'probe{s}.elf'))
        for s in range(5)
    }
    frame = counts[2] - counts[1]  # one SET_PARAM frame (10 bytes) with the ACK memory full
    commit = counts[3] - counts[4]  # COMMIT of the 1 s tripod (120 rows) after its upload
    per_row = commit / 120.0
    worst = 2 * MAX_ROWS * per_row  # a 1200-row gait failing at its last row, then the rebuild
    print(f'BENCH firmware_instructions_startup {counts[0]} instructions')
    print(f'BENCH firmware_instructions_frame {frame} instructions')
    print(f'BENCH firmware_instructions_commit_120_rows {commit} instructions')
    print(f'BENCH firmware_instructions_commit_worst {worst:.0f} instructions')
    row_ms = per_row * CPI_RANGE[1] / CLOCK_HZ * 1e3
    print(f'BENCH firmware_commit_ms_per_row_cpi_1_5 {row_ms:.2f} ms')
    print(
        f'# at 168 MHz, CPI {CPI_RANGE[0]}-{CPI_RANGE[1]}: one 10-byte frame {_ms(frame)} (a byte'
        f' at most that); COMMIT of a 1 s gait {_ms(commit)}; worst COMMIT (10 s period, fails'
        f' at its last row, the previous 10 s gait rebuilt) {_ms(worst)}'
    )
    return 0


if __name__ == '__main__':
    sys.exit(main())
