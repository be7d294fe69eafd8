#!/usr/bin/python3
"""Writes a copy of a replayed log (lcm-logger format) for a second replay of yaw fusion alone in which
the map's fixes end part-way: MAP_FIX after --end-s seconds of log are left out, and so are what yaw
fusion and the replay publish (POSE, STATUS, CONFIG) and the camera images (not needed after the tracker).
Prints how many events of each channel it kept and left out."""
import argparse
import collections
import struct
import sys

SYNC = 0xEDA1DA01
DROPPED = {"POSE", "STATUS", "CONFIG", "CAMERA_IMAGE"}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("log_in", help="a replay's output log with MAP_FIX, TRACKS and VO_DELTA in it")
    parser.add_argument("log_out")
    parser.add_argument("--end-s", type=float, required=True, help="leave out MAP_FIX this long after the log's first event")
    args = parser.parse_args()
    kept, left = collections.Counter(), collections.Counter()
    first = None
    with open(args.log_in, "rb") as src, open(args.log_out, "wb") as dst:
        offset = 0
        while True:
            header = src.read(28)
            if not header:
                break
            if len(header) < 28:
                sys.exit(f"{args.log_in}: truncated event header at byte {offset}")
            sync, number, utime, channel_len, data_len = struct.unpack(">IqqII", header)
            if sync != SYNC:
                sys.exit(f"{args.log_in}: no sync word at byte {offset}")
            channel = src.read(channel_len)
            data = src.read(data_len)
            if len(channel) != channel_len or len(data) != data_len:
                sys.exit(f"{args.log_in}: truncated event at byte {offset}")
            offset += 28 + channel_len + data_len
            name = channel.decode("utf-8", "replace")
            first = utime if first is None else first
            late_fix = name == "MAP_FIX" and utime - first > args.end_s * 1e6
            if name in DROPPED or late_fix:
                left[name] += 1
                continue
            kept[name] += 1
            dst.write(header + channel + data)
    for name in sorted(set(kept) | set(left)):
        print(f"{name:16s} kept {kept[name]:7d} left out {left[name]:7d}")


if __name__ == "__main__":
    main()
