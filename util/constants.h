/* Mathematical constants (strict C11 has no M_PI). */
#ifndef SKYFIT_UTIL_CONSTANTS_H
#define SKYFIT_UTIL_CONSTANTS_H

#define SF_PI 3.14159265358979323846264338327950288

#endif
