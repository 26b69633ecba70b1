/* Device plugins that go wrong, for plugin_device_test: built three times.
 *   BROKEN_NO_SYMBOL  igms_device_write_torque is missing
 *   BROKEN_ABI        igms_device_abi_version() returns 99
 *   (neither)         a good ABI whose ARGS choose the fault:
 *                     "fail-open"       open returns NULL with a reason
 *                     "block-ms=M,every=N"  every Nth read blocks M ms
 *                     "nan-every=N"     every Nth read gives a NaN position
 *                     "hold"            a device that reads the origin, for the good path */
#include <igms/device_plugin.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct igms_device {
  int block_ms, every, nan_every;
  long reads;
};

int igms_device_abi_version(void) {
#ifdef BROKEN_ABI
  return 99;
#else
  return IGMS_DEVICE_PLUGIN_ABI;
#endif
}

igms_device* igms_device_open(const char* args, char* error, int error_size) {
  if (strcmp(args, "fail-open") == 0) {
    snprintf(error, (size_t)error_size, "no device on /dev/ttyFAKE0 (permission denied)");
    return NULL;
  }
  igms_device* d = calloc(1, sizeof *d);
  if (sscanf(args, "block-ms=%d,every=%d", &d->block_ms, &d->every) != 2) d->block_ms = 0, d->every = 0;
  if (sscanf(args, "nan-every=%d", &d->nan_every) != 1) d->nan_every = 0;
  return d;
}

void igms_device_get_limits(igms_device* d, igms_device_limits* l) {
  (void)d;
  memset(l, 0, sizeof *l);
  l->max_force = NAN; /* nonsense: igms keeps its default */
  l->max_stiffness = 500.0;
}

int igms_device_read(igms_device* d, double t, igms_device_reading* r) {
  (void)t;
  ++d->reads;
  memset(r, 0, sizeof *r);
  if (d->every > 0 && d->reads % d->every == 0) {
    const struct timespec pause = {0, (long)d->block_ms * 1000000L};
    nanosleep(&pause, NULL);
  }
  if (d->nan_every > 0 && d->reads % d->nan_every == 0) r->position[0] = NAN;
  return 0;
}

int igms_device_write(igms_device* d, const double force[3]) {
  (void)d, (void)force;
  return 0;
}

#ifndef BROKEN_NO_SYMBOL
int igms_device_write_torque(igms_device* d, const double torque[3]) {
  (void)d, (void)torque;
  return 0;
}
#endif

void igms_device_close(igms_device* d) { free(d); }
