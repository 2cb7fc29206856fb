// The test host's message (v1, v2), multithread and memory suites, and
// fetchSuite.
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>

#include "ofx/ofx_test_host_internal.h"
#include "ofxMemory.h"  // after ofxCore.h, which it needs

namespace gdof::ofxtest::detail {

std::set<const void*>& effects_registry() {
    static std::set<const void*> s;
    return s;
}

namespace {

// ---------------------------------------------------------------------------
// Messages

std::string format(const char* fmt, va_list ap) {
    char buf[4096];
    std::vsnprintf(buf, sizeof buf, fmt ? fmt : "", ap);
    return buf;
}

ImageEffect* effect_of(void* handle) {
    std::lock_guard<std::mutex> lock(g_host->mu);
    return effects_registry().count(handle) ? static_cast<ImageEffect*>(handle) : nullptr;
}

OfxStatus message(void* handle, const char* type, const char*, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    const std::string m = format(fmt, ap);
    va_end(ap);
    if (ImageEffect* e = effect_of(handle)) {
        std::lock_guard<std::mutex> lock(e->mu);
        e->messages.push_back(std::string(type ? type : "") + ": " + m);
    }
    return kOfxStatOK;
}

OfxStatus setPersistentMessage(void* handle, const char* type, const char*, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    const std::string m = format(fmt, ap);
    va_end(ap);
    ImageEffect* e = effect_of(handle);
    if (!e) return kOfxStatErrBadHandle;
    std::lock_guard<std::mutex> lock(e->mu);
    e->persistent_type = type ? type : "";
    e->persistent_message = m;
    return kOfxStatOK;
}

OfxStatus clearPersistentMessage(void* handle) {
    ImageEffect* e = effect_of(handle);
    if (!e) return kOfxStatErrBadHandle;
    std::lock_guard<std::mutex> lock(e->mu);
    e->persistent_type.clear();
    e->persistent_message.clear();
    return kOfxStatOK;
}

const OfxMessageSuiteV1 kMessageSuiteV1 = {message};
const OfxMessageSuiteV2 kMessageSuiteV2 = {message, setPersistentMessage, clearPersistentMessage};

// ---------------------------------------------------------------------------
// Multithreading and memory

thread_local unsigned t_thread_index = 0;
thread_local bool t_spawned = false;

OfxStatus multiThread(OfxThreadFunctionV1 func, unsigned int n, void* arg) {
    if (!func) return kOfxStatErrBadHandle;
    if (n == 0) n = g_host->num_cpus;
    std::vector<std::thread> threads;
    for (unsigned i = 0; i < n; ++i)
        threads.emplace_back([=] {
            t_thread_index = i;
            t_spawned = true;
            func(i, n, arg);
        });
    for (auto& t : threads) t.join();
    return kOfxStatOK;
}
OfxStatus multiThreadNumCPUs(unsigned int* n) {
    if (!n) return kOfxStatErrBadHandle;
    *n = g_host->num_cpus;
    return kOfxStatOK;
}
OfxStatus multiThreadIndex(unsigned int* i) {
    if (!i) return kOfxStatErrBadHandle;
    *i = t_thread_index;
    return kOfxStatOK;
}
int multiThreadIsSpawnedThread() { return t_spawned ? 1 : 0; }
OfxStatus mutexCreate(OfxMutexHandle* m, int lock_count) {
    if (!m) return kOfxStatErrBadHandle;
    auto* mu = new std::recursive_mutex;
    for (int i = 0; i < lock_count; ++i) mu->lock();
    *m = reinterpret_cast<OfxMutexHandle>(mu);
    return kOfxStatOK;
}
OfxStatus mutexDestroy(const OfxMutexHandle m) {
    delete reinterpret_cast<std::recursive_mutex*>(m);
    return kOfxStatOK;
}
OfxStatus mutexLock(const OfxMutexHandle m) {
    reinterpret_cast<std::recursive_mutex*>(m)->lock();
    return kOfxStatOK;
}
OfxStatus mutexUnLock(const OfxMutexHandle m) {
    reinterpret_cast<std::recursive_mutex*>(m)->unlock();
    return kOfxStatOK;
}
OfxStatus mutexTryLock(const OfxMutexHandle m) {
    return reinterpret_cast<std::recursive_mutex*>(m)->try_lock() ? kOfxStatOK : kOfxStatFailed;
}

const OfxMultiThreadSuiteV1 kMultiThreadSuite = {multiThread, multiThreadNumCPUs, multiThreadIndex,
                                                  multiThreadIsSpawnedThread, mutexCreate, mutexDestroy,
                                                  mutexLock, mutexUnLock, mutexTryLock};

OfxStatus memoryAlloc(void*, size_t n, void** p) {
    if (!p) return kOfxStatErrBadHandle;
    *p = std::malloc(n ? n : 1);
    return *p ? kOfxStatOK : kOfxStatErrMemory;
}
OfxStatus memoryFree(void* p) {
    std::free(p);
    return kOfxStatOK;
}
const OfxMemorySuiteV1 kMemorySuite = {memoryAlloc, memoryFree};

}  // namespace

const void* fetch_suite(OfxPropertySetHandle, const char* name, int version) {
    if (!name) return nullptr;
    const std::string n = name;
    const void* s = nullptr;
    for (const std::string& w : g_host->withheld_suites)
        if (w == n) return nullptr;
    if (n == kOfxPropertySuite && version == 1) s = property_suite();
    else if (n == kOfxParameterSuite && version == 1) s = parameter_suite();
    else if (n == kOfxImageEffectSuite && version == 1) s = image_effect_suite();
    else if (n == kOfxMessageSuite && version == 1) s = &kMessageSuiteV1;
    else if (n == kOfxMessageSuite && version == 2) s = &kMessageSuiteV2;
    else if (n == kOfxMultiThreadSuite && version == 1) s = &kMultiThreadSuite;
    else if (n == kOfxMemorySuite && version == 1) s = &kMemorySuite;
    if (s) {
        std::lock_guard<std::mutex> lock(g_host->mu);
        g_host->suites_fetched.push_back(n + " v" + std::to_string(version));
    }
    return s;
}

}  // namespace gdof::ofxtest::detail
