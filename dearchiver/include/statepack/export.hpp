// STATEPACK_API marks the libraries' public interface. They are built with hidden visibility, so a
// shared libstatepack_dearchiver (or libstatepack_gl) exports exactly what carries this mark and its
// internals stay internal: free to change, and not clashing with an application's own symbols.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define STATEPACK_API __attribute__((visibility("default")))
#else
#define STATEPACK_API
#endif
