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

// Forced inlining where GCC would keep a hot function out of line (each use
// says why); plain inline elsewhere.
#if defined(__GNUC__) || defined(__clang__)
#define NEUROV_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define NEUROV_ALWAYS_INLINE inline
#endif
