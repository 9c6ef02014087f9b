#pragma once
// Whether this build runs under AddressSanitizer (the sanitize preset; g++ defines __SANITIZE_ADDRESS__,
// clang answers __has_feature): tests that time heavy work or exhaust the process's descriptors adapt.
namespace hrisim::testing {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderSanitizers = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderSanitizers = true;
#else
inline constexpr bool kUnderSanitizers = false;
#endif
#else
inline constexpr bool kUnderSanitizers = false;
#endif

}  // namespace hrisim::testing
