// SPDX-License-Identifier: MIT
// An lcm-spy plugin for gaussfilt's messages: every field of the last
// message on a channel, with the codes named (model MODEL_LINEAR, stage
// STAGE_UPDATE, status GF_ERR_GATED, filter FILTER_KF, measure MEASURE_XV)
// where lcm-spy's own viewer shows the raw bytes, and a node's status
// (node_status_t) track by track. lcm-spy finds it on the
// CLASSPATH (it is in gaussfilt_lcm_types.jar) and opens it on a
// double-click of a GF_ channel; its own viewer stays in the right-click
// menu ("Structure Viewer...").
//
// describe(message) is the text it shows, a plain function the tests call
// headless (sim/tests/java/GfSpyCheck.java).
package gaussfilt_spy;

import java.awt.BorderLayout;
import java.awt.Font;
import java.awt.event.ActionEvent;
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.util.Map;
import java.util.TreeMap;

import javax.swing.AbstractAction;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import javax.swing.JInternalFrame;
import javax.swing.JScrollPane;
import javax.swing.JTextArea;
import javax.swing.Timer;

import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

public class GfSpyPlugin implements SpyPlugin {
    // lcm-spy can find the jar twice (CLASSPATH and java.class.path) and
    // make one plugin for each: only the first takes channels, so that its
    // menu holds the action once.
    private static GfSpyPlugin first;

    // gaussfilt's types: the plugin takes their channels
    private static final Class<?>[] TYPES = {
        gaussfilt_lcm.belief_t.class, gaussfilt_lcm.control_t.class,
        gaussfilt_lcm.groundtruth_t.class, gaussfilt_lcm.measurement_t.class,
        gaussfilt_lcm.model_t.class, gaussfilt_lcm.particles_t.class,
        gaussfilt_lcm.node_status_t.class,
    };

    // The core's gf_status (include/gaussfilt/status.h), which
    // belief_t.status carries besides its own STATUS_* codes.
    private static final Map<Long, String> GF_STATUS = new TreeMap<>();
    static {
        GF_STATUS.put(0L, "GF_OK");
        GF_STATUS.put(-1L, "GF_ERR_ARG");
        GF_STATUS.put(-2L, "GF_ERR_NONFINITE");
        GF_STATUS.put(-3L, "GF_ERR_NOT_PSD");
        GF_STATUS.put(-4L, "GF_ERR_SINGULAR");
        GF_STATUS.put(-5L, "GF_ERR_GATED");
        GF_STATUS.put(-6L, "GF_ERR_UNDEFINED");
        GF_STATUS.put(-7L, "GF_ERR_MODEL");
    }

    public GfSpyPlugin() {
        synchronized (GfSpyPlugin.class) {
            if (first == null) {
                first = this;
            }
        }
    }

    public boolean canHandle(long fingerprint) {
        if (this != first) {
            return false;
        }
        for (Class<?> c : TYPES) {
            try {
                if (c.getField("LCM_FINGERPRINT").getLong(null) == fingerprint) {
                    return true;
                }
            } catch (ReflectiveOperationException e) {
                return false;
            }
        }
        return false;
    }

    public Action getAction(JDesktopPane jdp, ChannelData cd) {
        return new Viewer(jdp, cd);
    }

    // The name of code v of field f of class c: the constant of c named
    // F_* (F the field's name in capitals) holding v; for model, those of
    // measurement_t (MODEL_*), for filter those of belief_t (a node's
    // status); for status, also the core's gf_status. null when none.
    static String name(Class<?> c, String f, long v) {
        String prefix = f.toUpperCase() + "_";
        Class<?>[] where = {c, gaussfilt_lcm.measurement_t.class,
                            gaussfilt_lcm.belief_t.class};
        for (Class<?> w : where) {
            for (Field k : w.getFields()) {
                int m = k.getModifiers();
                if (!Modifier.isStatic(m) || !Modifier.isFinal(m) ||
                    !k.getName().startsWith(prefix) || k.getName().equals("LCM_FINGERPRINT")) {
                    continue;
                }
                try {
                    Object x = k.get(null);
                    if (x instanceof Number && ((Number) x).longValue() == v) {
                        return k.getName();
                    }
                } catch (IllegalAccessException e) {
                    return null;
                }
            }
        }
        return f.equals("status") ? GF_STATUS.get(v) : null;
    }

    // Whether field f of class c is a code with names: the class, or
    // measurement_t for model, has constants F_*.
    static boolean coded(Class<?> c, String f) {
        if (f.equals("status")) {
            return true;
        }
        String prefix = f.toUpperCase() + "_";
        for (Class<?> w : new Class<?>[] {c, gaussfilt_lcm.measurement_t.class,
                                          gaussfilt_lcm.belief_t.class}) {
            for (Field k : w.getFields()) {
                if (Modifier.isStatic(k.getModifiers()) && k.getName().startsWith(prefix) &&
                    !k.getName().equals("LCM_FINGERPRINT")) {
                    return true;
                }
            }
        }
        return false;
    }

    private static void value(StringBuilder s, Object v) {
        if (v == null) {
            s.append("(none)");
        } else if (v.getClass().isArray()) {
            int n = Array.getLength(v);
            boolean rows = n > 0 && Array.get(v, 0) != null && Array.get(v, 0).getClass().isArray();
            s.append(rows ? "[\n" : "[");
            for (int i = 0; i < n; i++) {
                if (rows) {
                    s.append("    ");
                }
                value(s, Array.get(v, i));
                s.append(rows ? "\n" : (i + 1 < n ? " " : ""));
            }
            s.append("]");
        } else if (v instanceof Double || v instanceof Float) {
            s.append(String.format("%.6g", ((Number) v).doubleValue()));
        } else {
            s.append(v);
        }
    }

    // Whether v is one of our structs (a field of node_status_t, say).
    private static boolean struct(Object v) {
        return v != null && v.getClass().getName().startsWith("gaussfilt_lcm.");
    }

    // Every public field of message m, one a line, codes named:
    // "stage = 2 STAGE_UPDATE", "status = -5 GF_ERR_GATED"; a struct's
    // fields indented under its name, an array of structs' one by one.
    public static String describe(Object m) {
        if (m == null) {
            return "(no message yet)";
        }
        StringBuilder s = new StringBuilder(m.getClass().getName()).append('\n');
        fields(s, m, "");
        return s.toString();
    }

    private static void fields(StringBuilder s, Object m, String indent) {
        Class<?> c = m.getClass();
        for (Field f : c.getFields()) {
            if (Modifier.isStatic(f.getModifiers())) {
                continue;
            }
            Object v;
            try {
                v = f.get(m);
            } catch (IllegalAccessException e) {
                continue;
            }
            s.append(indent).append(f.getName());
            if (struct(v)) {
                s.append(" =\n");
                fields(s, v, indent + "    ");
                continue;
            }
            if (v != null && v.getClass().isArray() &&
                v.getClass().getComponentType().getName().startsWith("gaussfilt_lcm.")) {
                int n = Array.getLength(v);
                s.append(" = ").append(n).append(n == 1 ? " entry\n" : " entries\n");
                for (int i = 0; i < n; i++) {
                    s.append(indent).append("  [").append(i).append("]\n");
                    fields(s, Array.get(v, i), indent + "    ");
                }
                continue;
            }
            s.append(" = ");
            value(s, v);
            if (v instanceof Number && !(v instanceof Double) && !(v instanceof Float) &&
                coded(c, f.getName())) {
                String n = name(c, f.getName(), ((Number) v).longValue());
                s.append(' ').append(n != null ? n : "(unknown code)");
            }
            s.append('\n');
        }
    }

    private static final class Viewer extends AbstractAction {
        private final JDesktopPane jdp;
        private final ChannelData cd;

        Viewer(JDesktopPane jdp, ChannelData cd) {
            super("gaussfilt: fields, codes named");
            this.jdp = jdp;
            this.cd = cd;
        }

        public void actionPerformed(ActionEvent e) {
            JInternalFrame frame = new JInternalFrame(cd.name, true, true, true, true);
            JTextArea text = new JTextArea();
            text.setEditable(false);
            text.setFont(new Font(Font.MONOSPACED, Font.PLAIN, 12));
            frame.setLayout(new BorderLayout());
            frame.add(new JScrollPane(text), BorderLayout.CENTER);
            frame.setSize(480, 360);
            jdp.add(frame);
            frame.setVisible(true);
            // lcm-spy keeps the channel's last message in cd.last: shown
            // five times a second while the window is open
            Timer timer = new Timer(200, ev -> {
                String now = describe(cd.last);
                if (!now.equals(text.getText())) {
                    text.setText(now);
                }
            });
            frame.addInternalFrameListener(new javax.swing.event.InternalFrameAdapter() {
                @Override
                public void internalFrameClosed(javax.swing.event.InternalFrameEvent ev) {
                    timer.stop();
                }
            });
            timer.start();
        }
    }
}
