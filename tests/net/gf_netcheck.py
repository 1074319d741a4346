#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""gf_netcheck: the network tests' listener and bookkeeper.

    gf_netcheck.py listen URL FILE
        records every belief on URL (GF_BELIEF_<n>) until SIGTERM, one line
        each: wall-clock time, track, seq, input_seq, stage, mean, cov.
    gf_netcheck.py faults WORKDIR
        reconciles a fault run (tests/net/net.sh faults): see check_faults.
    gf_netcheck.py split FILE T_STOP TRACKS_A TRACKS_B
        the scale-out verdict (tests/net/net.sh veth).
"""
import re
import signal
import sys
import time

RESULTS = ["applied", "duplicate", "out_of_order", "malformed",
           "type_mismatch", "bad_field", "unknown_channel", "track_limit",
           "nonfinite", "filter_error", "stale_session"]


def fail(msg):
    print("gf_netcheck: FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


def listen(url, path):
    import lcm
    from gaussfilt_lcm import belief_t
    out = open(path, "w")
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))

    def on_belief(channel, data):
        b = belief_t.decode(data)
        out.write("%.6f %d %d %d %d %r %r\n" % (
            time.time(), b.track, b.seq, b.input_seq, b.stage,
            list(b.mean[:b.n]),
            [list(r[:b.n]) for r in b.cov[:b.n]]))

    lc = lcm.LCM(url)
    # LCM holds 30 messages per subscription by default and drops the rest
    # of a burst (the node's restart is one).
    lc.subscribe("GF_BELIEF_-?[0-9]+", on_belief).set_queue_capacity(100000)
    print("gf_netcheck: ready listening on %s" % url, flush=True)
    while not stop:
        try:
            lc.handle_timeout(50)
        except OSError:  # a signal interrupted the wait
            time.sleep(0.001)  # (its handler runs right after)
    while lc.handle_timeout(50) > 0:
        pass
    out.close()


def beliefs(path):
    rows = []
    for line in open(path):
        p = line.split(" ", 5)
        mean_cov = p[5]
        rows.append({"t": float(p[0]), "track": int(p[1]), "seq": int(p[2]),
                     "input_seq": int(p[3]), "stage": int(p[4]),
                     "rest": mean_cov})
    return rows


def kv(line):
    return {k: int(v) for k, v in re.findall(r"(\w+)=(-?\d+)", line)}


def grep1(path, pattern):
    for line in open(path):
        if pattern in line:
            return line
    fail("no '%s' in %s" % (pattern, path))


def replay_node(events):
    """The node's admission rules (sim/node_core.h) over the wire order:
    returns the counters one node process must report, and the fate of
    every copy."""
    tracks, c, fates = {}, {r: 0 for r in RESULTS}, []
    c.update(gaps=0, resyncs=0, received=0)
    for (kind, track, session, seq, utime) in events:
        c["received"] += 1
        t = tracks.setdefault(track, {"has": False})
        r = "applied"
        if t["has"] and session != t["session"]:
            if session < t["session"]:
                r = "stale_session"
            else:
                t["has"] = False
                c["resyncs"] += 1
        if r == "applied" and t["has"]:
            if seq == t["seq"]:
                r = "duplicate"
            elif seq < t["seq"] or utime < t["utime"]:
                r = "out_of_order"
        if r == "applied":
            if t["has"]:
                c["gaps"] += seq - t["seq"] - 1
            t.update(has=True, session=session, seq=seq, utime=utime)
        c[r] += 1
        fates.append(r)
    return c, fates


def check_faults(work):
    """Reconciles a fault run exactly:
    1. the simulators' own counts == what the relay read (nothing lost
       between them);
    2. relay: in - dropped + duplicated == forwarded == log lines;
    3. the wire order from the relay's log, split at the pause around the
       node restart, replayed through the node's admission rules, gives
       exactly the counters each node process printed (received, applied,
       duplicate, out_of_order, stale_session, gaps, resyncs; every other
       rejection 0);
    4. every measurement sent ends as applied, rejected (reason) or lost;
    5. beliefs kept coming for every track after each restart; the
       restarted node started each track from the prior (STAGE_INIT, seq 0,
       then filters on); the restarted simulator's track re-initialised.
    """
    sims = [kv(grep1("%s/%s.out" % (work, s), "gf_sim: track="))
            for s in ("sim1a", "sim1b", "sim2", "sim3")]
    sent = sum(s["controls"] + s["measurements"] for s in sims)
    sent_meas = sum(s["measurements"] for s in sims)
    relay = kv(grep1(work + "/relay.out", "gf_relay: summary"))
    if relay["in"] != sent:
        fail("simulators sent %d, the relay read %d" % (sent, relay["in"]))
    wire, runs, marks = [], [[]], []
    for line in open(work + "/relay.log"):
        p = line.split()
        if not p:
            continue
        if p[0] in ("pause", "resume"):
            marks.append(p[0])
            if p[0] == "resume":
                runs.append([])
            continue
        ev = (p[1], int(p[2]), int(p[3]), int(p[4]), int(p[5]))
        wire.append((p[0], ev, int(p[6]) if p[0] == "fwd" else 0))
        if p[0] == "fwd":
            runs[-1].append(ev)
    fwd = sum(1 for w in wire if w[0] == "fwd")
    drops = sum(1 for w in wire if w[0] == "drop")
    dups = sum(1 for w in wire if w[0] == "fwd" and w[2] == 2)
    if marks != ["pause", "resume"] or len(runs) != 2:
        fail("expected one pause/resume in the relay log, got %s" % marks)
    if (relay["in"] - relay["dropped"] + relay["duplicated"] != relay["out"]
            or relay["out"] != fwd or relay["dropped"] != drops
            or relay["duplicated"] != dups):
        fail("relay counts do not add up: %s; log fwd=%d drop=%d dup=%d"
             % (relay, fwd, drops, dups))
    fates = []
    for k, run in enumerate(runs):
        want, f = replay_node(run)
        fates += f
        got = kv(grep1("%s/node%d.out" % (work, k + 1), "gf_node: summary"))
        for key in ["received", "gaps", "resyncs"] + RESULTS:
            if got.get(key) != want[key]:
                fail("node %d: %s=%s, the wire says %d"
                     % (k + 1, key, got.get(key), want[key]))
        print("node run %d: %s" % (k + 1, " ".join(
            "%s=%d" % (x, want[x]) for x in ["received", "applied",
                                               "duplicate", "out_of_order",
                                               "stale_session", "gaps",
                                               "resyncs"])))
    # 4. the fate of every measurement sent: applied if a copy was, else
    # the rejection of its copies, else lost (every copy dropped).
    fwd_ev = [w[1] for w in wire if w[0] == "fwd"]
    fate = {}
    for ev, r in zip(fwd_ev, fates):
        key = ev[1:4]
        if ev[0] == "meas" and (fate.get(key) != "applied"):
            fate[key] = r
    for w in wire:
        if w[0] == "drop" and w[1][0] == "meas":
            fate.setdefault(w[1][1:4], "lost on the wire")
    if len(fate) != sent_meas:
        fail("%d measurements sent, %d accounted for" % (sent_meas, len(fate)))
    tally = {}
    for r in fate.values():
        tally[r] = tally.get(r, 0) + 1
    print("measurements sent: %d = %s" % (sent_meas, " + ".join(
        "%d %s" % (v, k) for k, v in sorted(tally.items()))))
    print("faults injected: %d dropped, %d duplicated, %d reordered, "
          "%d delayed of %d messages" % (relay["dropped"],
                                         relay["duplicated"],
                                         relay["reordered"], relay["delayed"],
                                         relay["in"]))
    # 5. beliefs after the restarts.
    ev_t = {}
    for line in open(work + "/events"):
        name, t = line.split()
        ev_t[name] = float(t)
    rows = beliefs(work + "/beliefs")
    published = sum(kv(grep1("%s/node%d.out" % (work, k), "gf_node: summary"))
                    ["published"] for k in (1, 2))
    if len(rows) != published:
        fail("nodes published %d beliefs, the listener got %d"
             % (published, len(rows)))
    for track in (1, 2, 3):
        mine = [b for b in rows if b["track"] == track]
        for e in ("node_restarted", "sim_restarted"):
            after = [b for b in mine if b["t"] > ev_t[e] + 0.2]
            if len(after) < 20:
                fail("track %d: only %d beliefs after %s" % (track, len(after),
                                                             e))
        # The restarted node: its first belief of the track is the prior.
        after = [b for b in mine if b["t"] > ev_t["node_restarted"]]
        first = after[0]
        prior = ("[0.0, 0.0] [[0.0, 0.0], [0.0, 0.0]]" if track != 3 else
                 "[0.0, 0.0, 0.0] [[0.01, 0.0, 0.0], [0.0, 0.01, 0.0], "
                 "[0.0, 0.0, 10000.0]]")
        if (first["stage"] != 0 or first["seq"] != 0
                or first["rest"].strip() != prior or after[1]["seq"] != 1):
            fail("track %d: the restarted node did not start from the prior: "
                 "%s" % (track, first))
    inits = [b for b in rows if b["track"] == 1 and b["stage"] == 0
             and ev_t["sim_restarted"] < b["t"] < ev_t["node_restarted"]]
    if len(inits) != 1 or not inits[0]["rest"].startswith("[0.0, 0.0] "):
        fail("track 1: no single re-initialisation after the simulator "
             "restart: %s" % inits)
    print("beliefs: %d, for every track after both restarts; the restarted "
          "node began each track at the prior" % len(rows))


def check_split(path, t_stop, tracks_a, tracks_b):
    rows = beliefs(path)
    for tr in tracks_a + tracks_b:
        before = [b for b in rows if b["track"] == tr and b["t"] < t_stop]
        after = [b for b in rows if b["track"] == tr and b["t"] > t_stop + 0.3]
        print("track %d: %d beliefs before the stop, %d after"
              % (tr, len(before), len(after)))
        if len(before) < 20:
            fail("track %d: too few beliefs (%d)" % (tr, len(before)))
        if tr in tracks_b and after:
            fail("track %d: beliefs after its node stopped" % tr)
        if tr in tracks_a and len(after) < 20:
            fail("track %d: stopped with the other node" % tr)


if __name__ == "__main__":
    cmd = sys.argv[1]
    if cmd == "listen":
        listen(sys.argv[2], sys.argv[3])
    elif cmd == "faults":
        check_faults(sys.argv[2])
    elif cmd == "split":
        check_split(sys.argv[2], float(sys.argv[3]),
                    [int(x) for x in sys.argv[4].split(",")],
                    [int(x) for x in sys.argv[5].split(",")])
    else:
        fail("unknown command " + cmd)
