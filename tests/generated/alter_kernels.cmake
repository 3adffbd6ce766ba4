# Alters a package's dyngen_kernels.hpp (FILE) as another dyngen version's might differ: its
# neg_product (C = -(A B)) negates its result once more. The package's functions that call it
# then differ from the runtime, and a program that links this package beside an unaltered one
# shows whether each kept its own kernels (two_packages_test.cpp).
file(READ ${FILE} text)
set(loop "      product_block_of<block>(n - r0 < block ? n - r0 : block, n, c, r0, rows_begin, rows, A, B,\n                              C);\n")
string(FIND "${text}" "${loop}}\n" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${FILE}: neg_product's loop is not what alter_kernels.cmake expects")
endif()
string(REPLACE "${loop}}\n" "${loop}  for (int i = 0; i < n * n; ++i) C[i] = -C[i];  // altered\n}\n"
       altered "${text}")
file(WRITE ${FILE} "${altered}")
