// Prints "<class name> <LCM_FINGERPRINT as unsigned hex>" for every LCM type in a jar.
// Run with Java's single-file launcher: java -cp ucon_lcmtypes.jar:lcm.jar PrintFingerprints.java JAR
import java.util.Enumeration;
import java.util.jar.JarEntry;
import java.util.jar.JarFile;

public class PrintFingerprints {
  public static void main(String[] args) throws Exception {
    try (JarFile jar = new JarFile(args[0])) {
      Enumeration<JarEntry> entries = jar.entries();
      while (entries.hasMoreElements()) {
        String name = entries.nextElement().getName();
        if (!name.endsWith(".class") || name.contains("$")) continue;
        String cls = name.substring(0, name.length() - 6).replace('/', '.');
        Class<?> c = Class.forName(cls);
        long fp = c.getField("LCM_FINGERPRINT").getLong(null);
        System.out.println(cls + " " + Long.toHexString(fp));
      }
    }
  }
}
