/* Phase functions (SPEC §4, seed 004 §10.4.1.1), each normalised so that its
 * integral over the sphere of directions is 1. nu is the cosine between the
 * view direction (from the viewer outwards) and the direction towards the
 * sun: light continuing forwards into the eye has nu = 1. */
#ifndef SKYFIT_MODELS_PHASE_H
#define SKYFIT_MODELS_PHASE_H

#include "models/atmosphere.h"

double sf_phase_rayleigh(double nu);
double sf_phase_isotropic(void);
double sf_phase_henyey_greenstein(double g, double nu);
double sf_phase_cornette_shanks(double g, double nu);
double sf_phase_double_henyey_greenstein(double g1, double g2, double f, double nu);
/* Dispatch on p->kind; 0 for SF_PHASE_NONE. */
double sf_phase_value(const sf_phase *p, double nu);
/* The kind's JSON name ("rayleigh", ...), or NULL for SF_PHASE_NONE. */
const char *sf_phase_kind_name(sf_phase_kind kind);

#endif
