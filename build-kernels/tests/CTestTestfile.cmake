# CMake generated Testfile for 
# Source directory: /work/main/tests
# Build directory: /work/main/build-kernels/tests
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
add_test([=[test_model_parser]=] "/work/main/build-kernels/bin/test_model_parser")
set_tests_properties([=[test_model_parser]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;11;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_kinematics]=] "/work/main/build-kernels/bin/test_kinematics")
set_tests_properties([=[test_kinematics]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;15;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_forces]=] "/work/main/build-kernels/bin/test_forces")
set_tests_properties([=[test_forces]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;15;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_dense_cholesky]=] "/work/main/build-kernels/bin/test_dense_cholesky")
set_tests_properties([=[test_dense_cholesky]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;15;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_a01_pendulum]=] "/work/main/build-kernels/bin/test_a01_pendulum")
set_tests_properties([=[test_a01_pendulum]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;38;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_rigid_body_conservation]=] "/work/main/build-kernels/bin/test_rigid_body_conservation")
set_tests_properties([=[test_rigid_body_conservation]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;41;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_convergence_order]=] "/work/main/build-kernels/bin/test_convergence_order")
set_tests_properties([=[test_convergence_order]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;44;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_four_bar]=] "/work/main/build-kernels/bin/test_four_bar")
set_tests_properties([=[test_four_bar]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;47;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_step_allocates_nothing]=] "/work/main/build-kernels/bin/test_step_allocates_nothing")
set_tests_properties([=[test_step_allocates_nothing]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;52;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[test_cli]=] "/work/main/build-kernels/bin/test_cli")
set_tests_properties([=[test_cli]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;8;add_test;/work/main/tests/CMakeLists.txt;55;mbrt_add_test;/work/main/tests/CMakeLists.txt;0;")
add_test([=[example_control_loop]=] "/usr/bin/cmake" "-DMBRT_BUILD=/work/main/build-kernels" "-DMBRT_SOURCE=/work/main" "-DWORK=/work/main/build-kernels/tests/example_work" "-P" "/work/main/tests/example_control_loop.cmake")
set_tests_properties([=[example_control_loop]=] PROPERTIES  _BACKTRACE_TRIPLES "/work/main/tests/CMakeLists.txt;63;add_test;/work/main/tests/CMakeLists.txt;0;")
