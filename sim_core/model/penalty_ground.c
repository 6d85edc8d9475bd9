// The paper's ground as a MuJoCo engine plugin (mjPLUGIN_PASSIVE): a viscoelastic
// spring-damper at each foot. sim_core/model/ground.py says what it computes and why;
// sim_core/model/ground_build.py compiles this file (`make plugin`).
//
// Per foot whose sphere (centre: a site) dips below the floor (world z = 0):
//   normal      F_n = max(0, k_n depth - c_n v_z)                  (never pulls)
//   tangential  F_t = -k_t (p_xy - anchor_xy) - c_t v_xy            (anchored at touchdown)
//               |F_t| <= mu F_n: beyond it the anchor slides (Coulomb)
// applied at the foot's centre with mj_applyFT into qfrc_passive.
//
// State: per foot (anchor x, anchor y, touching) in plugin_state, which is part of a
// simulation's integration state (mjSTATE_PLUGIN), so mujoco.batch saves it with each
// simulation's row. plugin_data holds only what the model fixes (parameters, ids).
//
// Compiled with -ffp-contract=off: every product and sum rounds as written, as in the
// numba callback this replaces (its numbers are the reference, bit for bit).

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <mujoco/mujoco.h>

#ifndef PLUGIN_NAME  // set by ground_build.py: the name carries a hash of this file
#error "build with python -m sim_core.model.ground_build"
#endif

#define N_FEET 6
#define N_STATE (3 * N_FEET)

typedef struct {
  mjtNum k_n, c_n, k_t, c_t, mu, radius;
  int site[N_FEET];
  int body[N_FEET];
} Ground;

static const char* kAttributes[] = {
    "stiffness", "damping", "tangential_stiffness", "tangential_damping",
    "friction",  "radius",  "sites",
};
enum { nattribute = sizeof(kAttributes) / sizeof(kAttributes[0]) };

// a config attribute as a number; 0 and an error message when it is missing or not a number
static int read_number(const mjModel* m, int instance, const char* name, mjtNum* out) {
  const char* text = mj_getPluginConfig(m, instance, name);
  char* end = NULL;
  if (!text || !*text) {
    mju_warning("penalty ground: attribute '%s' is missing", name);
    return 0;
  }
  *out = strtod(text, &end);
  if (end == text || *end != '\0') {
    mju_warning("penalty ground: attribute '%s' is not a number: '%s'", name, text);
    return 0;
  }
  return 1;
}

static int nstate(const mjModel* m, int instance) {
  (void)m;
  (void)instance;
  return N_STATE;
}

static int init(const mjModel* m, mjData* d, int instance) {
  Ground* g = (Ground*)calloc(1, sizeof(Ground));
  if (!g) return -1;
  int ok = read_number(m, instance, "stiffness", &g->k_n) &&
           read_number(m, instance, "damping", &g->c_n) &&
           read_number(m, instance, "tangential_stiffness", &g->k_t) &&
           read_number(m, instance, "tangential_damping", &g->c_t) &&
           read_number(m, instance, "friction", &g->mu) &&
           read_number(m, instance, "radius", &g->radius);
  // sites: N_FEET site names separated by spaces, in the paper's leg order
  const char* sites = ok ? mj_getPluginConfig(m, instance, "sites") : NULL;
  char name[256];
  int nfound = 0;
  while (ok && sites && nfound < N_FEET) {
    while (*sites == ' ') sites++;
    size_t len = strcspn(sites, " ");
    if (len == 0 || len >= sizeof(name)) break;
    memcpy(name, sites, len);
    name[len] = '\0';
    int id = mj_name2id(m, mjOBJ_SITE, name);
    if (id < 0) {
      mju_warning("penalty ground: no site named '%s'", name);
      ok = 0;
      break;
    }
    g->site[nfound] = id;
    g->body[nfound] = m->site_bodyid[id];
    nfound++;
    sites += len;
  }
  if (ok && nfound != N_FEET) {
    mju_warning("penalty ground: 'sites' must name %d sites", N_FEET);
    ok = 0;
  }
  if (!ok) {
    free(g);
    return -1;
  }
  d->plugin_data[instance] = (uintptr_t)g;
  return 0;
}

static void destroy(mjData* d, int instance) {
  free((Ground*)d->plugin_data[instance]);
  d->plugin_data[instance] = 0;
}

static void copy(mjData* dest, const mjModel* m, const mjData* src, int instance) {
  (void)m;
  Ground* g = (Ground*)malloc(sizeof(Ground));
  if (g) memcpy(g, (const Ground*)src->plugin_data[instance], sizeof(Ground));
  dest->plugin_data[instance] = (uintptr_t)g;
}

// plugin_state is this instance's own slice (MuJoCo offsets it by plugin_stateadr)
static void reset(const mjModel* m, mjtNum* plugin_state, void* plugin_data, int instance) {
  (void)m;
  (void)plugin_data;
  (void)instance;
  mju_zero(plugin_state, N_STATE);
}

static void compute(const mjModel* m, mjData* d, int instance, int capability_bit) {
  if (!(capability_bit & mjPLUGIN_PASSIVE)) return;
  const Ground* g = (const Ground*)d->plugin_data[instance];
  mjtNum* state = d->plugin_state + m->plugin_stateadr[instance];
  const mjtNum k_n = g->k_n, c_n = g->c_n, k_t = g->k_t, c_t = g->c_t, mu = g->mu;
  for (int foot = 0; foot < N_FEET; foot++) {
    const int sid = g->site[foot];
    const mjtNum* pos = d->site_xpos + 3 * sid;
    const mjtNum depth = g->radius - pos[2];
    mjtNum* s = state + 3 * foot;
    if (depth <= 0.0) {
      s[2] = 0.0;  // lifted off: release the anchor
      continue;
    }
    mjtNum vel[6];  // (rot, lin), world frame
    mj_objectVelocity(m, d, mjOBJ_SITE, sid, vel, 0);
    const mjtNum vx = vel[3], vy = vel[4], vz = vel[5];
    mjtNum fn = k_n * depth - c_n * vz;
    if (fn < 0.0) fn = 0.0;
    if (s[2] == 0.0) {  // touchdown: anchor here
      s[0] = pos[0];
      s[1] = pos[1];
      s[2] = 1.0;
    }
    mjtNum fx = -k_t * (pos[0] - s[0]) - c_t * vx;
    mjtNum fy = -k_t * (pos[1] - s[1]) - c_t * vy;
    const mjtNum ft = fabs(sqrt(fx * fx + fy * fy));
    const mjtNum cap = mu * fn;
    if (ft > cap) {  // sliding: cap the force, move the anchor to match the spring
      const mjtNum scale = cap / ft;
      fx *= scale;
      fy *= scale;
      s[0] = pos[0] + (fx + c_t * vx) / k_t;
      s[1] = pos[1] + (fy + c_t * vy) / k_t;
    }
    const mjtNum force[3] = {fx, fy, fn};
    const mjtNum torque[3] = {0.0, 0.0, 0.0};
    const mjtNum point[3] = {pos[0], pos[1], pos[2]};
    mj_applyFT(m, d, force, torque, point, g->body[foot], d->qfrc_passive);
  }
}

mjPLUGIN_LIB_INIT(insect_gait_penalty_ground) {
  mjpPlugin plugin;
  mjp_defaultPlugin(&plugin);
  plugin.name = PLUGIN_NAME;
  plugin.capabilityflags = mjPLUGIN_PASSIVE;
  plugin.nattribute = nattribute;
  plugin.attributes = kAttributes;
  plugin.nstate = nstate;
  plugin.init = init;
  plugin.destroy = destroy;
  plugin.copy = copy;
  plugin.reset = reset;
  plugin.compute = compute;
  mjp_registerPlugin(&plugin);
}
