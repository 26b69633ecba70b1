#include "haptic_client/servo/servo_record.h"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace igms {

bool ServoRecord::write(const std::string& path, std::string* error) const {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    *error = path + ": " + std::strerror(errno);
    return false;
  }
  std::fprintf(f, "t,estimate_time,mode,tip_x,tip_y,tip_z,proxy_x,proxy_y,proxy_z,force_x,force_y,force_z,"
                  "rendered_x,rendered_y,rendered_z\n");
  // Vectors round-trip (%.17g): a check of the slew limit's 1 N step reads differences of values near
  // 10 N, which nine digits would round by 3e-8 N.
  for (const ServoRecordRow& r : rows_)
    std::fprintf(f, "%.6f,%.6f,%d,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", r.t,
                 r.estimate_time, r.mode, r.tip.x(), r.tip.y(), r.tip.z(), r.proxy.x(), r.proxy.y(), r.proxy.z(),
                 r.on_user.x(), r.on_user.y(), r.on_user.z(), r.rendered.x(), r.rendered.y(), r.rendered.z());
  if (std::ferror(f) || std::fclose(f) != 0) {
    *error = path + ": cannot write it";
    return false;
  }
  return true;
}

}  // namespace igms
