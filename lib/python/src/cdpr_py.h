/* SPDX-License-Identifier: BSD-3-Clause */
/// @file cdpr_py.h
/// The shim's functions (cdpr_py.c says what each does): the ABI the Python package cdprlib
/// binds with ctypes (lib/python/cdprlib/__init__.py declares the same signatures). Plain C
/// types only; the handle is opaque to Python.
#ifndef CDPR_PY_H
#define CDPR_PY_H

#include <stddef.h>

#define CDPR_PY_EXPORT __attribute__((visibility("default")))

typedef struct cdpr_py cdpr_py_t;

CDPR_PY_EXPORT const char *cdpr_py_status_name(int status);
CDPR_PY_EXPORT cdpr_py_t *cdpr_py_open(const char *scenario, int *status, char *msg, size_t cap);
CDPR_PY_EXPORT void cdpr_py_close(cdpr_py_t *h);
CDPR_PY_EXPORT void cdpr_py_info(const cdpr_py_t *h, long ints[5], double reals[3]);
CDPR_PY_EXPORT void cdpr_py_initial_pose(const cdpr_py_t *h, double pose[6]);
CDPR_PY_EXPORT double *cdpr_py_state(cdpr_py_t *h, int *dim);
CDPR_PY_EXPORT int cdpr_py_measure(const cdpr_py_t *h, double *out, int cap);
CDPR_PY_EXPORT int cdpr_py_nodes(const cdpr_py_t *h, int j, double *xyz, int cap);
CDPR_PY_EXPORT int cdpr_py_control(cdpr_py_t *h, double *rates);
CDPR_PY_EXPORT int cdpr_py_step(cdpr_py_t *h, int mode, const double *values, int *flags);
CDPR_PY_EXPORT void cdpr_py_work(const cdpr_py_t *h, long out[6]);
CDPR_PY_EXPORT int cdpr_py_ik(const cdpr_py_t *h, const double pose[6], double *length_m,
                              double *tension_cabin_N, double *tension_winch_N, double *H_N);
CDPR_PY_EXPORT int cdpr_py_catenary_solve(double w_N_per_m, double ea_N, double l_m, double h_m,
                                          double L0_m, double *H_N, double *va_N);
CDPR_PY_EXPORT void cdpr_py_catenary_point(double w_N_per_m, double ea_N, double H_N, double va_N,
                                           double s_m, double *x_m, double *z_m);

typedef struct cdpr_py_robot cdpr_py_robot_t;

CDPR_PY_EXPORT cdpr_py_robot_t *cdpr_py_robot_open(const char *path, int *status, char *msg,
                                                   size_t cap);
CDPR_PY_EXPORT void cdpr_py_robot_close(cdpr_py_robot_t *h);
CDPR_PY_EXPORT int cdpr_py_robot_info(const cdpr_py_robot_t *h, double nominal_pose[6]);
CDPR_PY_EXPORT int cdpr_py_robot_ik(const cdpr_py_robot_t *h, const double pose[6],
                                    const double f_ext[3], const double tau_ext[3],
                                    const double *bounds, double *length_m, double *tension_cabin_N,
                                    double *tension_winch_N, double *H_N, double *v_cabin_N,
                                    int verdict[2], double verdict_v[2], int *iterations);

#endif /* CDPR_PY_H */
