# SPDX-License-Identifier: MIT
"""LCM multicast self-test: publishes one message on URL and must hear it
back within a second (channel GF_SELFTEST, sim/gf_channels.h).

    python lcm_selftest.py URL      exit 0 if it works, 1 if not
"""
import sys

import lcm


def main():
    url = sys.argv[1]
    try:
        lc = lcm.LCM(url)
    except Exception as e:  # LCM raises a bare RuntimeError/IOError
        print(f"lcm_selftest: cannot open {url}: {e}", file=sys.stderr)
        return 1
    heard = []
    lc.subscribe("GF_SELFTEST", lambda channel, data: heard.append(data))
    lc.publish("GF_SELFTEST", b"gaussfilt self-test")
    for _ in range(10):
        lc.handle_timeout(100)
        if heard:
            return 0
    print(f"lcm_selftest: nothing came back on {url}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
