#!/usr/bin/env python3
"""Flash and static RAM of a firmware ELF (what `size` would say), and a budget check.

usage: elf-size.py FILE [--flash-kib N] [--ram-kib N]
"""
import struct
import sys


def sections(path):
    data = open(path, "rb").read()
    if data[:4] != b"\x7fELF" or data[4] != 1:
        sys.exit(f"{path}: not a 32-bit ELF file")
    shoff, = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
    hdrs = [struct.unpack_from("<IIIIIIIIII", data, shoff + i * shentsize) for i in range(shnum)]
    strtab = hdrs[shstrndx][4]
    for name, typ, flags, addr, off, size, *_ in hdrs:
        end = data.index(b"\0", strtab + name)
        yield data[strtab + name:end].decode(), typ, flags, size


def main():
    args = sys.argv[1:]
    path = args[0]
    budget = {k: float(v) for k, v in zip(args[1::2], args[2::2])}
    flash = ram = 0
    for name, typ, flags, size in sections(path):
        alloc, write, nobits = flags & 2, flags & 1, typ == 8
        if not alloc:
            continue
        if not nobits:
            flash += size  # code, constants and .data's initial values
        if write:
            ram += size  # .data, .bss, .uninit, the stack reservation if any
    print(f"firmware flash: {flash} bytes ({flash / 1024:.1f} KiB), static RAM: {ram} bytes ({ram / 1024:.1f} KiB)")
    ok = True
    if "--flash-kib" in budget and flash > budget["--flash-kib"] * 1024:
        print(f"flash over budget of {budget['--flash-kib']} KiB")
        ok = False
    if "--ram-kib" in budget and ram > budget["--ram-kib"] * 1024:
        print(f"static RAM over budget of {budget['--ram-kib']} KiB")
        ok = False
    sys.exit(0 if ok else 1)


main()
