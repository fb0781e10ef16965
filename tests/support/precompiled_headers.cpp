// The translation unit that carries the test programs' precompiled header (tests/CMakeLists.txt,
// settle_test_headers); it has no code of its own.
