// The target that builds the tests' precompiled header (tests/CMakeLists.txt, softwrist_test_pch); it has no tests
// of its own.
