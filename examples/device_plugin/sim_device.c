/* An example igms device plugin: a simulated 3-dof device held by a simulated
 * hand, the same hand as igms's scripted device (a mass on a spring-damper
 * pulled along timed targets, feeling the rendered force). It shows the whole
 * ABI of <igms/device_plugin.h>; a real device's plugin replaces the hand
 * with its SDK's calls (see docs/client.md, "A device plugin").
 *
 *   igms-haptic --device plugin:libigms_sim_device.so:TARGETS ...
 *
 * TARGETS is a text file (`igms-haptic --export-targets` writes one from a
 * scripted device's run): an optional line "hand MASS K B" (without it the
 * tip follows the targets exactly, as a scripted device without a hand), one line
 * "T X Y Z" per target (s; m, device frame), times increasing, and
 * "button T DOWN" lines (from T on, the main button is down: 1, or up: 0).
 * Lines starting with '#' and an "end T" line are ignored. The hand moves
 * between targets with the same smooth step as the scripted device. */
#include <igms/device_plugin.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_TARGETS 4096

struct igms_device {
  int n, nbuttons;
  double t[MAX_TARGETS], x[MAX_TARGETS][3];
  double button_t[MAX_TARGETS];
  int button_down[MAX_TARGETS];
  int has_hand;
  double mass, k, b;      /* the hand */
  double hand_x[3], hand_v[3], force[3];
  double last_t;          /* < 0 before the first read */
};

int igms_device_abi_version(void) { return IGMS_DEVICE_PLUGIN_ABI; }

igms_device* igms_device_open(const char* args, char* error, int error_size) {
  FILE* f = fopen(args, "r");
  if (!f) {
    snprintf(error, (size_t)error_size, "cannot read the targets file '%s'", args);
    return NULL;
  }
  igms_device* d = calloc(1, sizeof *d);
  d->mass = 0.3, d->k = 400.0, d->b = 25.0, d->last_t = -1.0;
  char line[256];
  while (fgets(line, sizeof line, f)) {
    double t, x, y, z;
    int down;
    if (line[0] == '#' || line[0] == '\n' || strncmp(line, "end ", 4) == 0) continue;
    if (sscanf(line, "hand %lf %lf %lf", &d->mass, &d->k, &d->b) == 3) {
      d->has_hand = 1;
      continue;
    }
    if (sscanf(line, "button %lf %d", &t, &down) == 2 && d->nbuttons < MAX_TARGETS) {
      d->button_t[d->nbuttons] = t, d->button_down[d->nbuttons++] = down;
      continue;
    }
    if (sscanf(line, "%lf %lf %lf %lf", &t, &x, &y, &z) != 4 || d->n == MAX_TARGETS ||
        (d->n > 0 && t <= d->t[d->n - 1])) {
      snprintf(error, (size_t)error_size, "%s: not 'T X Y Z' with increasing times: %.60s", args, line);
      fclose(f);
      free(d);
      return NULL;
    }
    d->t[d->n] = t, d->x[d->n][0] = x, d->x[d->n][1] = y, d->x[d->n][2] = z;
    ++d->n;
  }
  fclose(f);
  if (d->n == 0 || !(d->mass > 0 && d->k > 0 && d->b >= 0)) {
    snprintf(error, (size_t)error_size, "%s: no targets, or a hand without a positive mass and stiffness", args);
    free(d);
    return NULL;
  }
  return d;
}

void igms_device_get_limits(igms_device* d, igms_device_limits* l) {
  (void)d;
  memset(l, 0, sizeof *l); /* 0: igms keeps its defaults */
  /* A real device gives its own (an Omni: 3.3 N, 800 N/m). This one is a simulated hand, as the
   * scripted device's: no stiffness limit, so it feels what the scripted device's hand feels. */
  l->max_force = 3.3, l->max_force_step = 1.0, l->max_stiffness = INFINITY;
}

/* The scripted device's target: a smooth step between the targets around t. */
static void target(const igms_device* d, double t, double out[3]) {
  int k = 0;
  while (k < d->n && d->t[k] < t) ++k;
  if (k == 0 || k == d->n) {
    memcpy(out, d->x[k == 0 ? 0 : d->n - 1], sizeof d->x[0]);
    return;
  }
  const double u = (t - d->t[k - 1]) / (d->t[k] - d->t[k - 1]), s = u * u * (3.0 - 2.0 * u);
  for (int i = 0; i < 3; ++i) out[i] = d->x[k - 1][i] + s * (d->x[k][i] - d->x[k - 1][i]);
}

static int buttons_at(const igms_device* d, double t) {
  int down = 0;
  for (int k = 0; k < d->nbuttons; ++k)
    if (t >= d->button_t[k]) down = d->button_down[k];
  return down ? 1 : 0;
}

int igms_device_read(igms_device* d, double t, igms_device_reading* r) {
  double goal[3];
  target(d, t, goal);
  if (!d->has_hand) { /* the tip is the target; its velocity by difference */
    for (int i = 0; i < 3; ++i) {
      d->hand_v[i] = d->last_t >= 0 && t > d->last_t ? (goal[i] - d->hand_x[i]) / (t - d->last_t) : 0.0;
      d->hand_x[i] = goal[i];
    }
  } else {
    if (d->last_t < 0) memcpy(d->hand_x, goal, sizeof goal);
    const double dt = d->last_t >= 0 ? fmin(0.01, t - d->last_t) : 0.0;
    for (int i = 0; i < 3; ++i) { /* m xdd = k (goal - x) - b xd + F (semi-implicit Euler) */
      const double a = (d->k * (goal[i] - d->hand_x[i]) - d->b * d->hand_v[i] + d->force[i]) / d->mass;
      d->hand_v[i] += dt * a;
      d->hand_x[i] += dt * d->hand_v[i];
    }
  }
  d->last_t = t;
  memset(r, 0, sizeof *r);
  memcpy(r->position, d->hand_x, sizeof d->hand_x);
  memcpy(r->velocity, d->hand_v, sizeof d->hand_v);
  r->orientation[0] = 1.0;
  r->buttons = buttons_at(d, t);
  return 0;
}

int igms_device_write(igms_device* d, const double force[3]) {
  memcpy(d->force, force, sizeof d->force);
  return 0;
}

int igms_device_write_torque(igms_device* d, const double torque[3]) {
  (void)d, (void)torque; /* 3-dof */
  return 0;
}

void igms_device_close(igms_device* d) { free(d); }
