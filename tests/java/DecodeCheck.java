// Decodes a robot_state_t and a contacts_t that the C++ types encoded (hex on
// stdin, a line each) with the Java classes of igms_lcmtypes.jar, as lcm-spy
// does, and prints their fields.
import java.io.BufferedReader;
import java.io.InputStreamReader;

public class DecodeCheck {
  public static void main(String[] args) throws Exception {
    BufferedReader in = new BufferedReader(new InputStreamReader(System.in));
    igms.robot_state_t s = new igms.robot_state_t(bytes(in.readLine()));
    System.out.print("seq=" + s.seq + " nq=" + s.nq + " q0=" + s.q[0] + " nlinks=" + s.nlinks
        + " pose=" + s.link_poses[1][2]);
    igms.contacts_t c = new igms.contacts_t(bytes(in.readLine()));
    System.out.println(" contacts seq=" + c.seq + " n=" + c.ncontacts + " link_b=" + c.link_b[0] + " fz=" + c.force[0][2]);
  }

  static byte[] bytes(String line) {
    String hex = line.trim();
    byte[] data = new byte[hex.length() / 2];
    for (int i = 0; i < data.length; i++) data[i] = (byte) Integer.parseInt(hex.substring(2 * i, 2 * i + 2), 16);
    return data;
  }
}
