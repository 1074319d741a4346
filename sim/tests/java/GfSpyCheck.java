// SPDX-License-Identifier: MIT
// The lcm-spy plugin (sim/java/GfSpyPlugin.java), headless: lcm-spy's own
// class discovery (lcm.util.ClassDiscoverer over the CLASSPATH, as Spy
// does at start) finds it and makes it; it takes the channels of all seven
// message types and no other; its text names the codes (model, stage,
// status, filter, measure) of messages made here, and of every GF_ event
// of LOG, none unknown; a node's status shows its tracks one by one.
// Exits 1 on the first failure.
//
//   java -Djava.awt.headless=true -cp lcm.jar:gaussfilt_lcm_types.jar:. GfSpyCheck LOG
import java.io.ByteArrayInputStream;
import java.io.DataInputStream;
import java.io.EOFException;
import java.util.ArrayList;
import java.util.List;

import javax.swing.Action;

import gaussfilt_spy.GfSpyPlugin;
import lcm.logging.Log;
import lcm.spy.LCMTypeDatabase;
import lcm.spy.SpyPlugin;
import lcm.util.ClassDiscoverer;

public class GfSpyCheck {
    static void check(boolean ok, String what) {
        if (!ok) {
            System.err.println("GfSpyCheck: " + what);
            System.exit(1);
        }
    }

    static void has(String text, String line) {
        check(text.contains("\n" + line + "\n"), "no line '" + line + "' in:\n" + text);
    }

    public static void main(String[] args) throws Exception {
        final List<SpyPlugin> plugins = new ArrayList<>();
        ClassDiscoverer.findClasses((jar, cls) -> {
            for (Class<?> i : cls.getInterfaces()) {
                if (i.equals(SpyPlugin.class)) {
                    try {
                        plugins.add((SpyPlugin) cls.getConstructor().newInstance());
                    } catch (ReflectiveOperationException e) {
                        check(false, cls + ": " + e);
                    }
                }
            }
        });
        check(plugins.size() == 1 && plugins.get(0) instanceof GfSpyPlugin,
              "lcm-spy's discovery finds " + plugins.size() + " plugins, not GfSpyPlugin alone");
        SpyPlugin p = plugins.get(0);
        Action a = p.getAction(null, null); // as lcm-spy asks for its name
        System.out.println("GfSpyCheck: lcm-spy finds the plugin \"" + a.getValue(Action.NAME) + "\"");
        for (long fp : new long[] {gaussfilt_lcm.belief_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.control_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.groundtruth_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.measurement_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.model_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.particles_t.LCM_FINGERPRINT,
                                   gaussfilt_lcm.node_status_t.LCM_FINGERPRINT}) {
            check(p.canHandle(fp), String.format("does not take fingerprint %016x", fp));
        }
        check(!p.canHandle(0x0123456789abcdefL), "takes a foreign fingerprint");
        // found twice (lcm-spy reads CLASSPATH and java.class.path): the
        // second takes nothing, so the action is in the menu once
        check(!new GfSpyPlugin().canHandle(gaussfilt_lcm.belief_t.LCM_FINGERPRINT),
              "a second plugin takes the channels too");

        gaussfilt_lcm.belief_t b = new gaussfilt_lcm.belief_t();
        b.model = gaussfilt_lcm.measurement_t.MODEL_LINEAR;
        b.stage = gaussfilt_lcm.belief_t.STAGE_UPDATE;
        b.status = -5;
        b.filter = gaussfilt_lcm.belief_t.FILTER_KF;
        b.node = "n";
        b.n = 2;
        b.mean = new double[] {1.5, -2};
        b.cov = new double[][] {{1, 0}, {0, 4}};
        b.m = 1;
        b.innovation = new double[] {0.25};
        b.nis = 33.8;
        String t = GfSpyPlugin.describe(b);
        System.out.print(t);
        has(t, "model = 3 MODEL_LINEAR");
        has(t, "stage = 2 STAGE_UPDATE");
        has(t, "status = -5 GF_ERR_GATED");
        has(t, "filter = 5 FILTER_KF");
        has(t, "mean = [1.50000 -2.00000]");
        b.status = gaussfilt_lcm.belief_t.STATUS_NO_SUMMARY;
        has(GfSpyPlugin.describe(b), "status = -64 STATUS_NO_SUMMARY");
        b.status = -99;
        has(GfSpyPlugin.describe(b), "status = -99 (unknown code)");
        gaussfilt_lcm.model_t m = new gaussfilt_lcm.model_t();
        m.model = gaussfilt_lcm.measurement_t.MODEL_CAR;
        m.measure = gaussfilt_lcm.model_t.MEASURE_XV;
        t = GfSpyPlugin.describe(m);
        has(t, "model = 1 MODEL_CAR");
        has(t, "measure = 3 MEASURE_XV");
        // a node's status: its results and each track's, indented
        gaussfilt_lcm.node_status_t st = new gaussfilt_lcm.node_status_t();
        st.node = "n";
        st.host = "h";
        st.results = new gaussfilt_lcm.node_results_t();
        st.results.bad_field = 20;
        st.ntracks = 1;
        st.tracks = new gaussfilt_lcm.track_status_t[] {new gaussfilt_lcm.track_status_t()};
        st.tracks[0].track = 400;
        st.tracks[0].model = gaussfilt_lcm.measurement_t.MODEL_LINEAR;
        st.tracks[0].model_name = "target2d";
        st.tracks[0].filter = gaussfilt_lcm.belief_t.FILTER_KF;
        st.tracks[0].results = new gaussfilt_lcm.node_results_t();
        st.tracks[0].results.gated = 21;
        st.tracks[0].nis_last = 19.3;
        t = GfSpyPlugin.describe(st);
        System.out.print(t);
        has(t, "results =");
        has(t, "    bad_field = 20");
        has(t, "tracks = 1 entry");
        has(t, "    track = 400");
        has(t, "    model = 3 MODEL_LINEAR");
        has(t, "    filter = 5 FILTER_KF");
        has(t, "        gated = 21");
        has(t, "    nis_last = 19.3000");

        // every GF_ event of the log, decoded as lcm-spy does, described
        LCMTypeDatabase db = new LCMTypeDatabase();
        Log log = new Log(args[0], "r");
        long events = 0, named = 0;
        while (true) {
            Log.Event e;
            try {
                e = log.readNext();
            } catch (EOFException eof) {
                break;
            }
            if (e == null) {
                break;
            }
            if (!e.channel.startsWith("GF_")) {
                continue;
            }
            long fp = new DataInputStream(new ByteArrayInputStream(e.data)).readLong();
            Class<?> cls = db.getClassByFingerprint(fp);
            check(cls != null && p.canHandle(fp), e.channel + ": not taken by the plugin");
            String d = GfSpyPlugin.describe(cls.getConstructor(byte[].class).newInstance((Object) e.data));
            check(!d.contains("(unknown code)"), e.channel + ": a code without a name:\n" + d);
            named += d.split(" (MODEL|STAGE|FILTER|MEASURE|STATUS|GF)_[A-Z_0-9]+\n", -1).length - 1;
            events++;
        }
        log.close();
        check(events > 0, "no GF_ event in " + args[0]);
        System.out.printf("GfSpyCheck: %d GF_ events described, %d codes named, none unknown%n", events, named);
    }
}
