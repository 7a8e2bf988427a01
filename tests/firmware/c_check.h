/* The check of the C test programs: a failed condition is printed with its
 * place and counted, and the program goes on, so one run reports every
 * failure; main() returns non-zero when `failures` is not zero. */
#ifndef NEUROV_TEST_C_CHECK_H
#define NEUROV_TEST_C_CHECK_H

#include <stdio.h>

static int failures = 0;
#define CHECK(cond)                                                       \
  do {                                                                    \
    if (!(cond)) {                                                        \
      printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);            \
      ++failures;                                                         \
    }                                                                     \
  } while (0)

#endif
