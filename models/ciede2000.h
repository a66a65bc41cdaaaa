/* The CIEDE2000 colour difference (CIE 142-2001), implemented as in
 * G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula:
 * implementation notes, supplementary test data, and mathematical
 * observations", Color Res. Appl. 30(1) 21-30, 2005 (eq. 1-22), with the
 * parametric factors kL = kC = kH = 1. Hue angles in degrees, in [0, 360);
 * the mean hue and hue difference follow the paper's case rules, including
 * the "one chroma is zero" cases. Symmetric in its arguments. */
#ifndef SKYFIT_MODELS_CIEDE2000_H
#define SKYFIT_MODELS_CIEDE2000_H

/* ΔE00 between two CIELAB colours (L*, a*, b*). */
double sf_ciede2000(const double lab1[3], const double lab2[3]);

#endif
