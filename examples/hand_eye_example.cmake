# SPDX-License-Identifier: BSD-3-Clause
# 06: hand-eye calibration (nbs/registration/hand_eye.hpp), then the same planner run with the calibrated and the CAD
# hand-eye transform; core only. The object is the analytic sphere of nbs/sim/sphere_on_pedestal.hpp.
nbs_add_example(06_hand_eye_calibration SOURCES ${CMAKE_CURRENT_LIST_DIR}/06_hand_eye_calibration.cpp TEST)
