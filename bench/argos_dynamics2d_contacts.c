// Foot-bot contacts in ARGoS' dynamics2d, with ARGoS' own chipmunk: the reference for quirk (9)
// dynamics2d_contacts (docs/FIDELITY.md, "(9) dynamics2d_contacts"). Not part of the build: it needs the
// chipmunk sources of an ARGoS checkout (ilpincy/argos3 at b374f140), e.g.
//
//   git -C ARGOS_GIT_DIR archive b374f140 src/plugins/simulator/physics_engines/dynamics2d/chipmunk-physics | tar x
//   CP=src/plugins/simulator/physics_engines/dynamics2d/chipmunk-physics
//   gcc -O2 -std=gnu99 -I$CP/include -I$CP/include/chipmunk -DNDEBUG -o argos_contacts
//     bench/argos_dynamics2d_contacts.c $CP/src/[a-z]*.c $CP/src/constraints/[a-z]*.c -lm   (one line)
//   ./argos_contacts
//
// Bodies, shapes and joints as src/plugins/robots/foot-bot/simulator/dynamics2d_footbot_model.cpp and
// dynamics2d_velocity_control.cpp build them; a tick as dynamics2d_engine.cpp steps it (10 steps of 0.02 s
// at FORDYCA's 5 ticks/s, 10 solver iterations). Prints the displacement of each robot (m).
#include <chipmunk.h>
#include <math.h>
#include <stdio.h>

#define R 0.085036758
typedef struct {
  cpBody *body, *control;
  double left, right;
} Bot;
static cpSpace* space;
static Bot bots[16];
static int n_bots;

static void add(double x, double y, double heading, double speed) {
  Bot* k = &bots[n_bots++];
  k->body = cpSpaceAddBody(space, cpBodyNew(1.6, cpMomentForCircle(1.6, 0, R + R, cpvzero)));
  k->body->p = cpv(x, y);
  cpBodySetAngle(k->body, heading);
  cpShape* shape = cpSpaceAddShape(space, cpCircleShapeNew(k->body, R, cpvzero));
  shape->e = 0.0;
  shape->u = 0.7;
  k->control = cpBodyNew(INFINITY, INFINITY);
  cpConstraint* linear = cpSpaceAddConstraint(space, cpPivotJointNew2(k->body, k->control, cpvzero, cpvzero));
  linear->maxBias = 0;
  linear->maxForce = 15;
  cpConstraint* angular = cpSpaceAddConstraint(space, cpGearJointNew(k->body, k->control, 0, 1));
  angular->maxBias = 0;
  angular->maxForce = 150;
  k->left = k->right = speed;
}

static void tick(void) {
  for (int i = 0; i < n_bots; ++i) {
    Bot* k = &bots[i];
    if (k->left != 0 || k->right != 0) {
      const double v = 0.5 * (k->left + k->right), a = k->body->a;
      k->control->w = (k->right - k->left) / 0.14;
      k->control->v = cpv(v * cos(a), v * sin(a));
    } else {
      k->control->v = cpvzero;
      k->control->w = 0;
    }
  }
  for (int s = 0; s < 10; ++s) cpSpaceStep(space, 0.02);
}

/* Robots on a line along x, 1 mm apart: speed[i] (both wheels), heading 0 or pi (head on). */
static void run(const char* name, int n, const double* speed, const double* heading, double oblique, int ticks) {
  cpInitChipmunk();
  space = cpSpaceNew();
  space->iterations = 10;
  n_bots = 0;
  const double d = 2 * R + 0.001;
  if (oblique >= 0) {
    add(0, 0, 0, 0.1);
    add(d * cos(oblique), d * sin(oblique), 0, 0);
  } else {
    for (int i = 0; i < n; ++i) add(d * i, 0, heading[i], speed[i]);
  }
  double x0[16], y0[16];
  for (int i = 0; i < n_bots; ++i) x0[i] = bots[i].body->p.x, y0[i] = bots[i].body->p.y;
  for (int t = 0; t < ticks; ++t) tick();
  printf("%-28s %d ticks:", name, ticks);
  for (int i = 0; i < n_bots; ++i) printf(" (%+.4f, %+.4f)", bots[i].body->p.x - x0[i], bots[i].body->p.y - y0[i]);
  printf("\n");
  for (int i = 0; i < n_bots; ++i) cpBodyFree(bots[i].control);  // the space's own are left to exit
}

int main(void) {
  const double zero[6] = {0, 0, 0, 0, 0, 0}, pi2[2] = {0, M_PI};
  run("1 into 1 at rest", 2, (double[]){0.1, 0}, zero, -1, 50);
  run("1 into 2 at rest", 3, (double[]){0.1, 0, 0}, zero, -1, 50);
  run("2 into 1 at rest", 3, (double[]){0.1, 0.1, 0}, zero, -1, 50);
  run("2 into 2 at rest", 4, (double[]){0.1, 0.1, 0, 0}, zero, -1, 50);
  run("3 into 2 at rest", 5, (double[]){0.1, 0.1, 0.1, 0, 0}, zero, -1, 50);
  run("4 into 2 at rest", 6, (double[]){0.1, 0.1, 0.1, 0.1, 0, 0}, zero, -1, 50);
  run("head on 0.1 vs 0.1", 2, (double[]){0.1, 0.1}, pi2, -1, 50);
  run("head on 0.1 vs 0.05", 2, (double[]){0.1, 0.05}, pi2, -1, 50);
  const double angles[4] = {0.3, 0.5, 0.8, 1.0};
  for (int a = 0; a < 4; ++a) {
    char name[32];
    snprintf(name, sizeof name, "oblique %.1f rad", angles[a]);
    run(name, 2, NULL, NULL, angles[a], 30);
  }
  return 0;
}
