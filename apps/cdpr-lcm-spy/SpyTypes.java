// SPDX-License-Identifier: BSD-3-Clause
// cdpr-lcm-spy --check (docs/realtime.md, "lcm-spy"): lcm-spy's own type lookup
// (lcm.spy.LCMTypeDatabase, which scans the class path for LCM types) on the class path that
// cdpr-lcm-spy gives lcm-spy, for every message class in the cdpr types jar: one line per type
// with its fingerprint and whether lcm-spy finds it by that fingerprint. No display needed.
// Run as a single-file program: java -cp CLASSPATH SpyTypes.java TYPES_JAR
// Exit status 0 when the jar holds at least one type and lcm-spy finds every one, 1 otherwise.
import java.util.ArrayList;
import java.util.Collections;
import java.util.Enumeration;
import java.util.List;
import java.util.jar.JarEntry;
import java.util.jar.JarFile;
import lcm.spy.LCMTypeDatabase;

public class SpyTypes {
    public static void main(String[] args) throws Exception {
        List<String> names = new ArrayList<>();
        try (JarFile jar = new JarFile(args[0])) {
            for (Enumeration<JarEntry> e = jar.entries(); e.hasMoreElements();) {
                String n = e.nextElement().getName();
                if (n.startsWith("cdpr/") && n.endsWith(".class") && !n.contains("$")) {
                    names.add(n.substring(0, n.length() - 6).replace('/', '.'));
                }
            }
        }
        Collections.sort(names);
        LCMTypeDatabase db = new LCMTypeDatabase();
        int bad = 0;
        for (String name : names) {
            Class<?> c = Class.forName(name);
            long fp = c.getField("LCM_FINGERPRINT").getLong(null);
            Class<?> found = db.getClassByFingerprint(fp);
            boolean ok = found != null && found.getName().equals(name);
            System.out.println(String.format("%s %016x %s", name, fp,
                                             ok ? "found by lcm-spy" : "NOT found by lcm-spy"));
            bad += ok ? 0 : 1;
        }
        System.out.println(String.format("cdpr-lcm-spy: %d of %d cdpr types found by lcm-spy",
                                         names.size() - bad, names.size()));
        System.exit(names.isEmpty() || bad > 0 ? 1 : 0);
    }
}
