// Build configuration shared by every header.
#pragma once

// Exceptions are used only by convenience constructors that validate
// configuration; firmware builds (-fno-exceptions, or NEUROV_NO_EXCEPTIONS)
// use the noexcept create() functions, which return a ValidationError.
#if defined(__cpp_exceptions) && !defined(NEUROV_NO_EXCEPTIONS)
#define NEUROV_HAS_EXCEPTIONS 1
#else
#define NEUROV_HAS_EXCEPTIONS 0
#endif
