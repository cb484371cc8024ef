#!/usr/bin/env python3
"""Whether two GIFs show the same frames: the same size, frame count, frame places and delays, and
the same colour at every pixel of every frame. Exit status 0 if so, 1 if not, 2 on bad input.

gnuplot's gif terminal (libgd) places a few colours at other slots of the colour tables from run
to run, so the same movie is written as other bytes each time (measured: two reports from the
same runs, every movie's pixels identical, ~900 bytes apart). make_report.sh keeps the committed
movie when the new one shows the same frames (paper/make_report.sh).
Usage: gif_same_frames.py A.gif B.gif
"""
import sys


def lzw_indices(min_size, data):
    """One image's colour indices (bytes), decoded from its LZW sub-block data."""
    clear = 1 << min_size
    table = [bytes([i]) for i in range(clear)] + [b'', b'']
    size, prev = min_size + 1, None
    out = bytearray()
    bits = nbits = 0
    for byte in data:
        bits |= byte << nbits
        nbits += 8
        while nbits >= size:
            code = bits & ((1 << size) - 1)
            bits >>= size
            nbits -= size
            if code == clear:
                table, size, prev = table[:clear + 2], min_size + 1, None
                continue
            if code == clear + 1:
                return bytes(out)
            if code < len(table):
                entry = table[code]
            elif prev is not None and code == len(table):
                entry = prev + prev[:1]
            else:
                raise ValueError('bad LZW code')
            out += entry
            if prev is not None and len(table) < 4096:
                table.append(prev + entry[:1])
                if len(table) == 1 << size and size < 12:
                    size += 1
            prev = entry
    return bytes(out)


def frames(path, colour_ids):
    """(screen size, [(place and size, delay, pixels as colour ids)]) of a GIF. colour_ids: colour
    (3 bytes) -> id, shared by the files compared and filled as colours are met, so that the same
    colour has the same id whatever its slot."""
    b = open(path, 'rb').read()
    if b[:6] not in (b'GIF87a', b'GIF89a'):
        raise ValueError(f'{path}: not a GIF')

    def table(at, flags):
        n = 3 * (2 << (flags & 7)) if flags & 0x80 else 0
        return b[at:at + n], at + n

    gct, p = table(13, b[10])
    out, delay = [], 0
    while p < len(b) and b[p] != 0x3B:
        if b[p] == 0x21:
            if b[p + 1] == 0xF9:
                delay = b[p + 4] | b[p + 5] << 8
            p += 2
            while b[p]:
                p += b[p] + 1
            p += 1
        elif b[p] == 0x2C:
            place = b[p + 1:p + 9]
            lct, p = table(p + 10, b[p + 9])
            ct = lct or gct
            ids = bytearray(256)
            for i in range(len(ct) // 3):
                ids[i] = colour_ids.setdefault(ct[3 * i:3 * i + 3], len(colour_ids)) % 256
            min_size, data = b[p], bytearray()
            p += 1
            while b[p]:
                data += b[p + 1:p + 1 + b[p]]
                p += b[p] + 1
            p += 1
            out.append((place, delay, lzw_indices(min_size, data).translate(bytes(ids))))
        else:
            raise ValueError(f'{path}: unexpected block 0x{b[p]:02x} at byte {p}')
    return b[6:10], out


def main(a, b):
    colour_ids = {}
    fa, fb = frames(a, colour_ids), frames(b, colour_ids)
    if len(colour_ids) > 256:  # ids wrapped: not comparable this way, taken as other frames
        return 1
    return 0 if fa == fb else 1


if __name__ == '__main__':
    if len(sys.argv) != 3:
        print('usage: gif_same_frames.py A.gif B.gif', file=sys.stderr)
        sys.exit(2)
    try:
        sys.exit(main(sys.argv[1], sys.argv[2]))
    except (OSError, ValueError, IndexError) as e:
        print(f'gif_same_frames.py: {e}', file=sys.stderr)
        sys.exit(2)
