/*
 * Tests of the shim's contract that Rust cannot reach, run against a real Embree 3 or 4 by
 * tools/check-embree4.sh:
 *   - the library's runtime version (major.minor.patch) against the headers the shim was
 *     compiled with: they must come from the same release;
 *   - how many bytes past our headers' RTCRayHit / RTCRayHit8 the library writes (instPrimID,
 *     instance levels): none when headers and library are the same release (anything else means
 *     a different build configuration), else at most the padded unions' GLINT_HIT_SLACK;
 *   - the hit (t == 1, geomID 0) and occlusion's convention (tfar = -inf on a hit);
 *   - errors: taken once, per thread, never leaking into the next commit;
 *   - lifetimes: a scene outlives its freed device; the live-handle count returns to zero.
 * The kernel-dependent checks (overruns, hits, occlusion, the lifetimes check's hit) run once
 * per instruction set the CPU supports, on a device made with Embree's "isa=..." config; each
 * run first reads, from what a verbose device prints, which kernels Embree really selected (it
 * falls back to SSE2 silently on an ISA name it does not know).
 *
 * It includes shim.c to see its private types and constants. Build (see the script):
 *   cc -std=c11 -DGLINT_EMBREE_MAJOR=4 -Iffi -isystem INCLUDE ffi/shim_test.c -lembree4 -lpthread
 * Exits 0 when every check passes, 1 otherwise; prints what it measured.
 */
/* dup, dup2, fileno (capturing Embree's verbose output) under -std=c11. */
#define _POSIX_C_SOURCE 200809L

#include "shim.c"

#include <pthread.h>
#include <unistd.h>

static int failures = 0;

#define CHECK(cond, ...)                                                                         \
    do {                                                                                         \
        if (!(cond)) {                                                                           \
            fprintf(stderr, "FAIL %s:%d: ", __FILE__, __LINE__);                                 \
            fprintf(stderr, __VA_ARGS__);                                                        \
            fprintf(stderr, "\n");                                                               \
            ++failures;                                                                          \
        }                                                                                        \
    } while (0)

/* One triangle in the z = 0 plane covering (0,0)-(1,0)-(0,1). */
static const float TRIANGLE[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
static const uint32_t TRIANGLE_INDICES[3] = {0, 1, 2};

static glint_scene *triangle_scene(glint_device *d) {
    glint_scene *s = glint_scene_new(d, GLINT_BUILD_MEDIUM, 0);
    if (s == NULL || glint_scene_add_triangles(s, TRIANGLE, 3, TRIANGLE_INDICES, 1) != 0 ||
        glint_scene_commit(s) != 0) {
        return NULL;
    }
    return s;
}

/* A ray straight down onto the triangle's interior point (0.25, 0.25). */
static glint_ray down_ray(void) {
    glint_ray r = {{0.25f, 0.25f, 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY};
    return r;
}

/* The triangle lies at t == 1 on the down ray. Embree's kernels divide by a reciprocal
 * estimate refined once, so the t they report depends on the ISA: exactly 1 with AVX-512's
 * rcp14, 0.99999994 (1 ulp below) with SSE2 to AVX2's rcp (Embree 3.13.5 and 4.3.3 alike). */
#define GLINT_T_ULPS 4

/* How many floats lie between t and 1 (a large number for a NaN or a negative t). */
static long ulps_from_one(float t) {
    float one = 1.0f;
    int32_t a, b;
    memcpy(&a, &t, sizeof a);
    memcpy(&b, &one, sizeof b);
    return a > b ? (long)a - b : (long)b - a;
}

/* Index one past the last byte of buf[from, to) that differs from the fill byte; `from` if
 * none does. */
static size_t written_end(const unsigned char *buf, size_t from, size_t to, unsigned char fill) {
    size_t end = from;
    for (size_t i = from; i < to; ++i) {
        if (buf[i] != fill) {
            end = i + 1;
        }
    }
    return end;
}

/* Returns whether headers and library are the same release (major.minor.patch). */
static int check_versions(glint_device *d) {
    long library = (long)rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_VERSION);
    long library_major = (long)rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_VERSION_MAJOR);
    printf("headers: Embree %s (RTC_VERSION %d, RTC_MAX_INSTANCE_LEVEL_COUNT %d)\n",
           RTC_VERSION_STRING, RTC_VERSION, RTC_MAX_INSTANCE_LEVEL_COUNT);
    printf("library: Embree %ld.%ld.%ld (ray masks %s)\n", library / 10000, library / 100 % 100,
           library % 100,
           rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) ? "on"
                                                                                   : "off");
    CHECK(glint_embree_major() == RTC_VERSION_MAJOR, "shim major %d, headers %d",
          glint_embree_major(), RTC_VERSION_MAJOR);
    CHECK(library_major == RTC_VERSION_MAJOR, "library major %ld, headers %d", library_major,
          RTC_VERSION_MAJOR);
    CHECK(library == RTC_VERSION,
          "headers are Embree %s but the library is Embree %ld.%ld.%ld: headers and library are "
          "from different releases",
          RTC_VERSION_STRING, library / 10000, library / 100 % 100, library % 100);
    return library == RTC_VERSION;
}

/* Fills the padded single-ray union with `fill`, traces the down ray and reports how far past
 * our struct RTCRayHit the library wrote. */
static size_t overrun1(glint_scene *s, unsigned char fill, float *t) {
    GLINT_QUERY_ARGS(args, Intersect, 0);
    padded_rayhit p;
    memset(&p, fill, sizeof p);
    glint_ray in = down_ray();
    load_ray(&p.rh.ray, &in);
    p.rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    p.rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    GLINT_INTERSECT1(s->scene, &p.rh, args);
    CHECK(p.rh.hit.geomID == 0 && ulps_from_one(p.rh.ray.tfar) <= GLINT_T_ULPS,
          "rtcIntersect1 missed (geomID %u, t %.9g, %ld ulps from 1)", p.rh.hit.geomID,
          (double)p.rh.ray.tfar, ulps_from_one(p.rh.ray.tfar));
    *t = p.rh.ray.tfar;
    return written_end((const unsigned char *)&p, sizeof p.rh, sizeof p, fill) - sizeof p.rh;
}

/* The same for a packet of 8 (all lanes valid, all hitting). */
static size_t overrun8(glint_scene *s, unsigned char fill) {
    GLINT_QUERY_ARGS(args, Intersect, 0);
    padded_rayhit8 p __attribute__((aligned(64)));
    int valid[8] __attribute__((aligned(32)));
    glint_ray in[8];
    for (int k = 0; k < 8; ++k) {
        in[k] = down_ray();
    }
    memset(&p, fill, sizeof p);
    load_ray8(&p.rh.ray, in, 8, valid);
    for (int k = 0; k < 8; ++k) {
        p.rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
        p.rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
    }
    GLINT_INTERSECT8(valid, s->scene, &p.rh, args);
    for (int k = 0; k < 8; ++k) {
        CHECK(p.rh.hit.geomID[k] == 0, "rtcIntersect8 lane %d missed", k);
    }
    return written_end((const unsigned char *)&p, sizeof p.rh, sizeof p, fill) - sizeof p.rh;
}

/* same_release: headers and library are one release, so they must agree on the structs. */
static void check_struct_overruns(glint_scene *s, int same_release) {
    /* Two fills, so a written byte that happens to equal one fill is still seen. */
    float t = 0.0f;
    size_t a1 = overrun1(s, 0xA5, &t), b1 = overrun1(s, 0x5A, &t);
    size_t a8 = overrun8(s, 0xA5), b8 = overrun8(s, 0x5A);
    size_t past1 = a1 > b1 ? a1 : b1;
    size_t past8 = a8 > b8 ? a8 : b8;
    printf("rtcIntersect1 hit at t = %.9g (%ld ulps from 1; up to %d allowed)\n", (double)t,
           ulps_from_one(t), GLINT_T_ULPS);
    printf("rtcIntersect1 wrote %zu bytes past our struct RTCRayHit (%zu bytes); room %d\n", past1,
           sizeof(struct RTCRayHit), GLINT_HIT_SLACK);
    printf("rtcIntersect8 wrote %zu bytes past our struct RTCRayHit8 (%zu bytes); room %d\n", past8,
           sizeof(struct RTCRayHit8), 8 * GLINT_HIT_SLACK);
    CHECK(past1 <= GLINT_HIT_SLACK, "single-ray overrun %zu exceeds the slack", past1);
    CHECK(past8 <= 8 * GLINT_HIT_SLACK, "packet overrun %zu exceeds the slack", past8);
    if (same_release) {
        CHECK(past1 == 0 && past8 == 0,
              "the library wrote past our hit structs (%zu and %zu bytes) although headers and "
              "library are both Embree %s: they come from builds with different configurations "
              "(RTC_MAX_INSTANCE_LEVEL_COUNT, instance arrays)",
              past1, past8, RTC_VERSION_STRING);
    }
}

static void check_occlusion_convention(glint_scene *s) {
    GLINT_QUERY_ARGS(args, Occluded, 0);
    struct RTCRay r;
    glint_ray in = down_ray();
    load_ray(&r, &in);
    GLINT_OCCLUDED1(s->scene, &r, args);
    CHECK(isinf(r.tfar) && r.tfar < 0.0f, "occluded ray has tfar %g, expected -inf",
          (double)r.tfar);
    in.tfar = 0.5f; /* ends above the triangle */
    load_ray(&r, &in);
    GLINT_OCCLUDED1(s->scene, &r, args);
    CHECK(r.tfar == 0.5f, "unoccluded ray's tfar changed to %g", (double)r.tfar);
}

/* Makes Embree raise an error on the calling thread: a vertex buffer slot that does not exist. */
/* glint_all_hits1 reports every surface along a ray, directly and through instances, counts
 * past its capacity without writing there, and the closest-hit query is unchanged by the
 * scene flag it needs. */
static void check_all_hits(glint_device *d) {
    const float lower[9] = {0, 0, -1, 1, 0, -1, 0, 1, -1};
    glint_scene *s = glint_scene_new(d, GLINT_BUILD_MEDIUM, 0);
    CHECK(s != NULL && glint_scene_add_triangles(s, TRIANGLE, 3, TRIANGLE_INDICES, 1) == 0 &&
              glint_scene_add_triangles(s, lower, 3, TRIANGLE_INDICES, 1) == 1 &&
              glint_scene_commit(s) == 0,
          "the two-triangle scene did not build");
    glint_ray r = down_ray();
    glint_hit hits[4];
    memset(hits, 0, sizeof hits);
    size_t n = glint_all_hits1(s, &r, hits, 4);
    CHECK(n == 2, "all_hits found %zu surfaces, expected 2", n);
    CHECK(n == 2 && hits[0].geom_id + hits[1].geom_id == 1 && hits[0].inst_id == GLINT_INVALID_ID,
          "all_hits reported geometries %u and %u", hits[0].geom_id, hits[1].geom_id);
    glint_hit one[2];
    memset(one, 0xAB, sizeof one);
    CHECK(glint_all_hits1(s, &r, one, 1) == 2, "all_hits did not count past its capacity");
    CHECK(one[1].geom_id == 0xABABABABu, "all_hits wrote past its capacity");
    r.tfar = 1.5f; /* the upper triangle only */
    CHECK(glint_all_hits1(s, &r, hits, 4) == 1, "all_hits ignored tfar");
    glint_hit closest;
    r = down_ray();
    glint_intersect1(s, &r, &closest, 1, 0);
    CHECK(closest.geom_id == 0, "closest hit %u, expected the upper triangle", closest.geom_id);
    glint_scene_free(s);

    glint_scene *child = triangle_scene(d);
    glint_scene *top = glint_scene_new(d, GLINT_BUILD_MEDIUM, 0);
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    const float below[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -2};
    CHECK(child != NULL && top != NULL && glint_scene_add_instance(top, child, identity) == 0 &&
              glint_scene_add_instance(top, child, below) == 1 && glint_scene_commit(top) == 0,
          "the instanced scene did not build");
    r = down_ray();
    n = glint_all_hits1(top, &r, hits, 4);
    CHECK(n == 2 && hits[0].geom_id == 0 && hits[1].geom_id == 0 &&
              hits[0].inst_id + hits[1].inst_id == 1,
          "all_hits through instances: %zu hits", n);
    glint_scene_free(top);
    glint_scene_free(child);
}

static void raise_error(glint_device *d) {
    RTCGeometry g = rtcNewGeometry(d->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 99, RTC_FORMAT_FLOAT3, 12, 3);
    rtcReleaseGeometry(g);
}

static void *raise_and_take_on_thread(void *device) {
    raise_error((glint_device *)device);
    int code = glint_device_take_error((glint_device *)device, NULL, 0);
    CHECK(code != 0, "the raising thread did not get its own error");
    return NULL;
}

static void *raise_on_thread(void *device) {
    raise_error((glint_device *)device);
    return NULL;
}

static void check_errors(glint_device *d) {
    char message[256];
    raise_error(d);
    int code = glint_device_take_error(d, message, sizeof message);
    printf("raised error: code %d, \"%s\"\n", code, message);
    CHECK(code != 0 && message[0] != '\0', "error not reported (code %d)", code);
    CHECK(glint_device_take_error(d, message, sizeof message) == 0, "error taken twice");

    /* An error that nobody took must not fail the next commit on this thread. */
    raise_error(d);
    glint_scene *s = glint_scene_new(d, GLINT_BUILD_LOW, 0);
    CHECK(glint_scene_add_triangles(s, TRIANGLE, 3, TRIANGLE_INDICES, 1) == 0, "add failed");
    code = glint_scene_commit(s);
    CHECK(code == 0, "commit returned a stale error %d", code);
    glint_scene_free(s);
    glint_device_take_error(d, NULL, 0);

    /* An error raised on another thread is that thread's to take, never this one's. */
    void *(*const bodies[2])(void *) = {raise_and_take_on_thread, raise_on_thread};
    for (int i = 0; i < 2; ++i) {
        pthread_t thread;
        CHECK(pthread_create(&thread, NULL, bodies[i], d) == 0, "pthread_create");
        pthread_join(thread, NULL);
    }
    code = glint_device_take_error(d, message, sizeof message);
    CHECK(code == 0, "took another thread's error %d (\"%s\")", code, message);
}

static void check_lifetimes(const char *config) {
    int64_t before = glint_live_handles();
    glint_device *d = glint_device_new(config);
    CHECK(d != NULL, "device: %s", glint_last_creation_error());
    if (d == NULL) {
        return;
    }
    glint_scene *s = glint_scene_new(d, GLINT_BUILD_HIGH, 1);
    glint_device_free(d); /* before the scene is filled, built and used */
    CHECK(glint_scene_add_triangles(s, TRIANGLE, 3, TRIANGLE_INDICES, 1) == 0, "add failed");
    CHECK(glint_scene_commit(s) == 0, "commit failed");
    glint_ray r = down_ray();
    glint_hit h;
    glint_intersect1(s, &r, &h, 1, 1);
    CHECK(h.geom_id == 0 && ulps_from_one(h.t) <= GLINT_T_ULPS,
          "hit after the device was freed: geom %u t %.9g", h.geom_id, (double)h.t);
    glint_scene_free(s);
    CHECK(glint_live_handles() == before, "live handles %lld, expected %lld",
          (long long)glint_live_handles(), (long long)before);
}

/* ---- one run per instruction set ------------------------------------------------------ */

/* Embree's name for AVX-512 in "isa=": "avx512" since 3.12.2 (so in every Embree 4),
 * "avx512skx" before. An unknown name is not an error: Embree silently runs SSE2. */
#if RTC_VERSION >= 31202
#define GLINT_ISA_AVX512 "avx512"
#else
#define GLINT_ISA_AVX512 "avx512skx"
#endif

typedef struct isa_run {
    const char *name;   /* Embree's config name */
    const char *target; /* Embree's name for the target in its verbose output */
} isa_run;

static const isa_run ISAS[] = {
    {"sse2", "SSE2"}, {"sse4.2", "SSE4.2"}, {"avx", "AVX"}, {"avx2", "AVX2"},
    {GLINT_ISA_AVX512, "AVX512"},
};
#define ISA_COUNT (sizeof ISAS / sizeof ISAS[0])

/* Whether the CPU (and OS) support ISAS[i]; __builtin_cpu_supports takes only literals. */
static int cpu_supports(size_t i) {
#if defined(GLINT_X86) && (defined(__GNUC__) || defined(__clang__))
    switch (i) {
    case 0:
        return __builtin_cpu_supports("sse2");
    case 1:
        return __builtin_cpu_supports("sse4.2");
    case 2:
        return __builtin_cpu_supports("avx");
    case 3:
        return __builtin_cpu_supports("avx2");
    case 4: /* Embree's AVX512 target: Skylake-X's set */
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
               __builtin_cpu_supports("avx512cd");
    default:
        return 0;
    }
#else
    (void)i;
    return 0;
#endif
}

/* Whether `word` is one of the space-separated words of line[0, len). */
static int has_word(const char *line, size_t len, const char *word) {
    size_t n = strlen(word);
    for (size_t i = 0; i + n <= len; ++i) {
        if ((i == 0 || line[i - 1] == ' ') && strncmp(line + i, word, n) == 0 &&
            (i + n == len || line[i + n] == ' ')) {
            return 1;
        }
    }
    return 0;
}

/* The line of `text` that starts with `prefix` (its length in *len, without the prefix), or
 * NULL. */
static const char *line_after(const char *text, const char *prefix, size_t *len) {
    const char *p = strstr(text, prefix);
    if (p == NULL) {
        return NULL;
    }
    p += strlen(prefix);
    const char *end = strchr(p, '\n');
    *len = end != NULL ? (size_t)(end - p) : strlen(p);
    return p;
}

/* Which kernels a device made with `config` runs, read from what Embree prints with verbose=1
 * (the same lines in Embree 3 and 4):
 *     "    Targets : SSE SSE2 ... AVX2  (supported)"        what the config enabled
 *     "              SSE2 SSE4.2 AVX AVX2 AVX512  (compile time enabled)"
 * *enabled: the widest of ISAS the config enabled; *kernels: the widest both enabled and in the
 * library (the kernels Embree selects). Either is NULL when unreadable. */
static void selected_targets(const char *config, const char **enabled, const char **kernels) {
    *enabled = *kernels = NULL;
    char verbose_config[128];
    snprintf(verbose_config, sizeof verbose_config, "%s,verbose=1", config);
    char text[16384];
    size_t n = 0;
    FILE *capture = tmpfile();
    int saved = -1;
    fflush(stdout);
    if (capture != NULL && (saved = dup(STDOUT_FILENO)) >= 0 &&
        dup2(fileno(capture), STDOUT_FILENO) >= 0) {
        RTCDevice device = rtcNewDevice(verbose_config); /* prints as it is created */
        fflush(stdout);
        if (device != NULL) {
            rtcReleaseDevice(device);
        }
        fflush(stdout);
        dup2(saved, STDOUT_FILENO);
        rewind(capture);
        n = fread(text, 1, sizeof text - 1, capture);
    }
    if (saved >= 0) {
        close(saved);
    }
    if (capture != NULL) {
        fclose(capture);
    }
    text[n] = '\0';
    size_t supported_len = 0, compiled_len = 0;
    const char *supported = line_after(text, "\n    Targets : ", &supported_len);
    const char *compiled = supported != NULL ? line_after(supported, "\n", &compiled_len) : NULL;
    if (supported == NULL || compiled == NULL || strstr(compiled, "compile time") == NULL) {
        return;
    }
    for (size_t i = 0; i < ISA_COUNT; ++i) {
        if (has_word(supported, supported_len, ISAS[i].target)) {
            *enabled = ISAS[i].target;
            if (has_word(compiled, compiled_len, ISAS[i].target)) {
                *kernels = ISAS[i].target;
            }
        }
    }
}

/* The kernel-dependent checks on a device configured with "isa=<name>". Returns the kernels
 * Embree ran them on (isa->target, unless the library lacks those), NULL if unknown. */
static const char *run_isa(const isa_run *isa, int same_release) {
    char config[64];
    snprintf(config, sizeof config, "isa=%s", isa->name);
    const char *enabled = NULL, *kernels = NULL;
    selected_targets(config, &enabled, &kernels);
    printf("\n-- %s: %s kernels\n", config, kernels != NULL ? kernels : "(unknown)");
    CHECK(enabled != NULL && kernels != NULL,
          "could not read which kernels Embree selected for \"%s\" (its verbose output)", config);
    CHECK(enabled == NULL || strcmp(enabled, isa->target) == 0,
          "Embree enabled up to %s for \"%s\", not %s: it does not know the name", enabled,
          config, isa->target);
    if (kernels != NULL && strcmp(kernels, isa->target) != 0) {
        printf("note: this library has no %s kernels; %s's ran instead\n", isa->target, kernels);
    }

    glint_device *d = glint_device_new(config);
    CHECK(d != NULL, "device \"%s\": %s", config, glint_last_creation_error());
    if (d == NULL) {
        return NULL;
    }
    glint_scene *s = triangle_scene(d);
    CHECK(s != NULL, "the one-triangle scene did not build (%s)", config);
    if (s != NULL) {
        check_struct_overruns(s, same_release);
        check_occlusion_convention(s);
        glint_scene_free(s);
    }
    glint_device_free(d);
    check_lifetimes(config);
    return kernels;
}

/* Appends " word" (or "word" first) to the list in buf[0, size). */
static void append(char *buf, size_t size, const char *word) {
    size_t used = strlen(buf);
    snprintf(buf + used, size - used, "%s%s", used > 0 ? " " : "", word);
}

int main(void) {
    setvbuf(stdout, NULL, _IOLBF, 0); /* FAIL lines (stderr) stay in order in a piped log */
    glint_set_denormal_modes();
#if defined(GLINT_X86) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
#endif
    glint_device *d = glint_device_new(NULL);
    if (d == NULL) {
        fprintf(stderr, "FAIL: no Embree device: %s\n", glint_last_creation_error());
        return 1;
    }
    int same_release = check_versions(d);
    check_errors(d);
    check_all_hits(d);
    glint_device_free(d);

    /* ran: on the ISA's own kernels; other: asked for, but Embree ran other (or unknown)
     * kernels; unsupported: the CPU lacks the ISA. */
    char ran[128] = "", other[256] = "", unsupported[128] = "";
    int runs = 0;
    for (size_t i = 0; i < ISA_COUNT; ++i) {
        if (!cpu_supports(i)) {
            append(unsupported, sizeof unsupported, ISAS[i].name);
            continue;
        }
        ++runs;
        const char *kernels = run_isa(&ISAS[i], same_release);
        if (kernels != NULL && strcmp(kernels, ISAS[i].target) == 0) {
            append(ran, sizeof ran, ISAS[i].name);
        } else {
            char entry[64];
            snprintf(entry, sizeof entry, "%s(on %s kernels)", ISAS[i].name,
                     kernels != NULL ? kernels : "unknown");
            append(other, sizeof other, entry);
        }
    }
    if (runs == 0) { /* not x86, or a compiler without __builtin_cpu_supports */
        printf("\n-- default device (no per-ISA runs on this platform)\n");
        d = glint_device_new(NULL);
        glint_scene *s = d != NULL ? triangle_scene(d) : NULL;
        CHECK(s != NULL, "the one-triangle scene did not build");
        if (s != NULL) {
            check_struct_overruns(s, same_release);
            check_occlusion_convention(s);
            glint_scene_free(s);
        }
        glint_device_free(d);
        check_lifetimes(NULL);
    }
    printf("\nISAs run: %s\n", ran[0] != '\0' ? ran : "(none: default device only)");
    if (other[0] != '\0') {
        printf("ISAs asked for but run on other kernels: %s\n", other);
    }
    if (unsupported[0] != '\0') {
        printf("ISAs not run (this CPU lacks them): %s\n", unsupported);
    }
    CHECK(glint_live_handles() == 0, "%lld handles leaked", (long long)glint_live_handles());
    printf("%s: %d failure(s)\n", failures == 0 ? "shim_test passed" : "shim_test FAILED",
           failures);
    return failures == 0 ? 0 : 1;
}
