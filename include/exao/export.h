/* exao/export.h: EXAO_API marks the declarations libexao exports; everything else in the
 * library is hidden. Shared by the C header (exao/exao.h) and the C++ header (exao/exao.hpp).
 *
 * Define EXAO_STATIC when linking a static build of the library (the in-tree exao_api_static),
 * so that Windows builds do not expect DLL imports. EXAO_BUILDING is defined by the library's
 * own build only. */
#ifndef EXAO_EXPORT_H
#define EXAO_EXPORT_H

#if defined(EXAO_STATIC)
#define EXAO_API
#elif defined(_WIN32) || defined(__CYGWIN__)
#if defined(EXAO_BUILDING)
#define EXAO_API __declspec(dllexport)
#else
#define EXAO_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define EXAO_API __attribute__((visibility("default")))
#else
#define EXAO_API
#endif

#endif /* EXAO_EXPORT_H */
