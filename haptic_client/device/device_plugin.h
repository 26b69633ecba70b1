/* igms device plugin ABI: a haptic device in a shared library of its own,
 * loaded by `igms-haptic --device plugin:PATH.so[:ARGS]` with dlopen. Plain C,
 * so a plugin needs no igms headers but this one and no C++ ABI match.
 * Installed as <igms/device_plugin.h>.
 *
 * Units and frames: metres, seconds, newtons, newton metres; the device's own
 * frame (x, y, z right-handed, as the device reports them); igms maps it to
 * the scene with the scene's workspace scale and offset. Orientation is a unit
 * quaternion w x y z, device frame <- tip.
 *
 * Threads and timing: read and write are called once each per servo cycle
 * (1 kHz) from the servo loop's thread, which runs on absolute deadlines.
 * They must return within tens of microseconds: no blocking I/O, no locks
 * another thread may hold long, no allocation. igms measures each call and
 * reports the p99 and maximum, and counts calls over 100 us as overruns.
 * open and close run outside the loop and may take their time.
 *
 * Every function below must be exported (extern "C", default visibility).
 * A plugin returns IGMS_DEVICE_PLUGIN_ABI from igms_device_abi_version();
 * igms refuses a plugin built against another version. */
#ifndef IGMS_DEVICE_PLUGIN_H
#define IGMS_DEVICE_PLUGIN_H

#ifdef __cplusplus
extern "C" {
#endif

#define IGMS_DEVICE_PLUGIN_ABI 1

typedef struct igms_device igms_device; /* the plugin's own state, opaque to igms */

typedef struct {
  double max_force;        /* N the device renders continuously */
  double max_force_step;   /* N the rendered force may change in one cycle */
  double max_stiffness;    /* N/m the device renders stably (K < 2b/T); a stiffer coupling is felt
                              scaled down to it. INFINITY: a simulated device, no limit */
  double max_torque;       /* N m (0: a 3-dof device) */
  double max_torque_step;  /* N m per cycle */
  double workspace_min[3]; /* m, device frame */
  double workspace_max[3];
} igms_device_limits;

typedef struct {
  double position[3];         /* tip, m */
  double velocity[3];         /* m/s */
  int has_orientation;        /* 1: a 6-dof device (orientation and angular velocity are set) */
  double orientation[4];      /* w x y z */
  double angular_velocity[3]; /* rad/s */
  int buttons;                /* bit 0: the main button (push or grab) */
} igms_device_reading;

/* IGMS_DEVICE_PLUGIN_ABI. */
int igms_device_abi_version(void);
/* Opens the device; args is what follows the library's path after a colon ("" without).
 * NULL on failure, with a one-line reason in error (error_size bytes, NUL-terminated). */
igms_device* igms_device_open(const char* args, char* error, int error_size);
/* The device's limits; igms clamps and scales its coupling to them. */
void igms_device_get_limits(igms_device* device, igms_device_limits* limits);
/* The tip now; t: s since the servo loop started. 0 on success. */
int igms_device_read(igms_device* device, double t, igms_device_reading* reading);
/* The force to render now, N, device frame (already within the limits). 0 on success. */
int igms_device_write(igms_device* device, const double force[3]);
/* The torque to render now, N m (a 3-dof device ignores it and returns 0). */
int igms_device_write_torque(igms_device* device, const double torque[3]);
/* Releases the device (forces to zero first). */
void igms_device_close(igms_device* device);

#ifdef __cplusplus
}
#endif

#endif /* IGMS_DEVICE_PLUGIN_H */
