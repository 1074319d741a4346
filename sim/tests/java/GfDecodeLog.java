// SPDX-License-Identifier: MIT
// Decodes every event of an LCM log whose channel starts with GF_ the way
// lcm-spy does: the class comes from the fingerprint (lcm.spy.LCMTypeDatabase
// scans the CLASSPATH, gaussfilt_lcm_types.jar included), then the class's
// byte[] constructor decodes the payload. Headless: prints a count per type
// and exits 1 if any GF_ event has no class or does not decode.
//
//   java -cp lcm.jar:gaussfilt_lcm_types.jar:. GfDecodeLog LOG [EXPECT]
//
// EXPECT: the number of GF_ events there must be.
import java.io.ByteArrayInputStream;
import java.io.DataInputStream;
import java.io.EOFException;
import java.util.Map;
import java.util.TreeMap;

import lcm.logging.Log;
import lcm.spy.LCMTypeDatabase;

public class GfDecodeLog {
    public static void main(String[] args) throws Exception {
        if (args.length < 1) {
            System.err.println("usage: GfDecodeLog LOG [EXPECT]");
            System.exit(2);
        }
        LCMTypeDatabase db = new LCMTypeDatabase();
        Log log = new Log(args[0], "r");
        Map<String, Integer> byType = new TreeMap<>();
        long events = 0, bad = 0;
        while (true) {
            Log.Event e;
            try {
                e = log.readNext();
            } catch (EOFException eof) {
                break;
            }
            if (e == null)
                break;
            if (!e.channel.startsWith("GF_"))
                continue;
            events++;
            long fp = new DataInputStream(new ByteArrayInputStream(e.data)).readLong();
            Class<?> cls = db.getClassByFingerprint(fp);
            if (cls == null) {
                if (bad++ < 5)
                    System.err.printf("no class for %s (fingerprint %016x)%n", e.channel, fp);
                continue;
            }
            try {
                cls.getConstructor(byte[].class).newInstance((Object) e.data);
            } catch (Exception ex) {
                if (bad++ < 5)
                    System.err.printf("%s: %s does not decode: %s%n", e.channel, cls.getName(), ex.getCause());
                continue;
            }
            byType.merge(cls.getName(), 1, Integer::sum);
        }
        log.close();
        for (Map.Entry<String, Integer> t : byType.entrySet())
            System.out.printf("GfDecodeLog: %s %d%n", t.getKey(), t.getValue());
        System.out.printf("GfDecodeLog: %d GF_ events, %d undecodable%n", events, bad);
        if (bad != 0 || events == 0 || (args.length > 1 && events != Long.parseLong(args[1])))
            System.exit(1);
    }
}
