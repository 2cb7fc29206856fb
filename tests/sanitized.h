// GDOF_TEST_SANITIZED: defined when the test is built with a sanitizer that
// replaces the allocator (ASan, TSan, MSan), under which what the process
// holds in memory says nothing about the library (freed blocks are kept in
// quarantine, glibc's accounting is bypassed).
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define GDOF_TEST_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define GDOF_TEST_SANITIZED 1
#endif
