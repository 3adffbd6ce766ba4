// The translation unit that builds the check harnesses' precompiled header (CMakeLists.txt).
