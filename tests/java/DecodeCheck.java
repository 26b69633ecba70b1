// Decodes a robot_state_t that the C++ types encoded (hex on stdin) with the
// Java classes of igms_lcmtypes.jar, as lcm-spy does, and prints its fields.
import java.io.BufferedReader;
import java.io.InputStreamReader;

public class DecodeCheck {
  public static void main(String[] args) throws Exception {
    String hex = new BufferedReader(new InputStreamReader(System.in)).readLine().trim();
    byte[] data = new byte[hex.length() / 2];
    for (int i = 0; i < data.length; i++) data[i] = (byte) Integer.parseInt(hex.substring(2 * i, 2 * i + 2), 16);
    igms.robot_state_t s = new igms.robot_state_t(data);
    System.out.println("seq=" + s.seq + " nq=" + s.nq + " q0=" + s.q[0] + " nlinks=" + s.nlinks
        + " pose=" + s.link_poses[1][2]);
  }
}
