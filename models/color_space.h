/* Colour spaces for the spectral reference and the error metrics (SPEC §6
 * "spectral radiance converted to XYZ/sRGB", §12 "ΔE2000 after exposure"):
 * CIE XYZ <-> linear sRGB, XYZ -> CIELAB, and the exposure + tone map that
 * turns a linear sRGB radiance into the displayed colour compared by ΔE2000.
 *
 * The XYZ -> linear sRGB matrix is the 4-decimal IEC 61966-2-1 matrix of
 * data/physical/xyz_to_srgb.csv (D65 white; tests/test_color_space.c checks
 * the constant against the file). sRGB -> XYZ is its exact inverse, so a
 * round trip is exact to rounding. */
#ifndef SKYFIT_MODELS_COLOR_SPACE_H
#define SKYFIT_MODELS_COLOR_SPACE_H

/* [R,G,B]^T = M [X,Y,Z]^T, rows R, G, B (xyz_to_srgb.csv). */
extern const double sf_xyz_to_linear_srgb_matrix[3][3];

void sf_xyz_to_linear_srgb(const double xyz[3], double rgb[3]);
void sf_linear_srgb_to_xyz(const double rgb[3], double xyz[3]);
/* The inverse of sf_xyz_to_linear_srgb_matrix (Cramer's rule, double). */
void sf_linear_srgb_to_xyz_matrix(double m[3][3]);

/* XYZ of linear sRGB (1, 1, 1): the D65 white of this matrix
 * (Y = 1 up to the matrix's rounding). */
void sf_srgb_white_xyz(double white[3]);

/* CIE 1976 L*a*b* of xyz relative to the white white_xyz (CIE 15:2004
 * eq. 8.1-8.3, with the exact constants delta = 6/29: f(t) = t^(1/3) for
 * t > delta^3, else t / (3 delta^2) + 4/29; negative t stays on the linear
 * branch, so out-of-gamut colours still get a finite L*a*b*). */
void sf_xyz_to_lab(const double xyz[3], const double white_xyz[3], double lab[3]);

/* The displayed colour of a linear sRGB radiance (SPEC §12, seed 000 §11.4
 * and §11.5): multiplied by the exposure, tone mapped per channel with
 * t(x) = 1 - exp(-x), then converted to L*a*b* relative to the sRGB white
 * (so display white (1,1,1) is L* = 100, a* = b* = 0). */
void sf_display_lab(const double linear_srgb[3], double exposure, double lab[3]);
/* The same without exposure or tone map: a colour already in [0, 1], as a
 * transmittance picture shows it. */
void sf_linear_lab(const double linear_srgb[3], double lab[3]);

/* SPEC §12's exposures (seed 000 §11.4): 16 at dawn (sun below the
 * horizon), 2 for a viewer in space (above the top of the atmosphere),
 * else 1. Dawn wins over space. */
double sf_standard_exposure(double sun_elevation_deg, int viewer_in_space);

#endif
