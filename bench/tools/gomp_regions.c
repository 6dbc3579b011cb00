// Counts OpenMP parallel regions per outlined function: a profiling aid, not part of the build.
//   gcc -O2 -shared -fPIC bench/tools/gomp_regions.c -o /tmp/gomp_regions.so -ldl
//   LD_PRELOAD=/tmp/gomp_regions.so build/release/app/aeroform-cli flow CASE.json
//   sort -rn /tmp/gomp_regions.txt | head   # count, address, object file, offset in it
//   addr2line -f -C -e OBJECT 0xOFFSET     # the function a region belongs to
// Every GOMP_parallel call is counted, nested (inactive) ones too; only top-level regions wake
// the other threads. libgomp only (GCC's OpenMP).
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

typedef void (*region_fn)(void*);
enum { kMaxRegions = 4096 };
static void* functions[kMaxRegions];
static long counts[kMaxRegions];
static int known;
static char lock;  // guards functions/known (nested regions start on several threads at once)
static void (*gomp_parallel)(region_fn, void*, unsigned, unsigned);

static void report(void) {
    FILE* out = fopen("/tmp/gomp_regions.txt", "w");
    if (!out) return;
    for (int i = 0; i < known; ++i) {
        Dl_info info;
        if (dladdr(functions[i], &info) && info.dli_fname) {
            fprintf(out, "%ld %p %s %lx\n", counts[i], functions[i], info.dli_fname,
                    (unsigned long)((char*)functions[i] - (char*)info.dli_fbase));
        } else {
            fprintf(out, "%ld %p ? 0\n", counts[i], functions[i]);
        }
    }
    fclose(out);
}

void GOMP_parallel(region_fn fn, void* data, unsigned threads, unsigned flags) {
    if (!gomp_parallel) {
        gomp_parallel = (void (*)(region_fn, void*, unsigned, unsigned))dlsym(RTLD_NEXT, "GOMP_parallel");
        atexit(report);
    }
    while (__atomic_test_and_set(&lock, __ATOMIC_ACQUIRE)) {
    }
    int i = 0;
    while (i < known && functions[i] != (void*)fn) ++i;
    if (i == known && known < kMaxRegions) functions[known++] = (void*)fn;
    if (i < kMaxRegions) ++counts[i];
    __atomic_clear(&lock, __ATOMIC_RELEASE);
    gomp_parallel(fn, data, threads, flags);
}
