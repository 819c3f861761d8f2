/*
 * glint's shim over Embree 3 and Embree 4. See shim.h for the contract.
 *
 * GLINT_EMBREE_MAJOR (3 or 4) is set by build.rs from the headers it found. The API
 * differences this file hides:
 *   - Embree 3 passes an RTCIntersectContext before the ray; Embree 4 passes optional
 *     RTCIntersectArguments / RTCOccludedArguments after it. Both init helpers are inline.
 *   - Embree 4 enables ray masking by default (a ray mask of 0 misses everything): every ray
 *     here carries mask 0xFFFFFFFF and geometries keep their default mask.
 *   - Hit structs grow with RTC_MAX_INSTANCE_LEVEL_COUNT and, from 4.3, instPrimID (when the
 *     library has RTC_GEOMETRY_INSTANCE_ARRAY). Rays and hits live on this file's stack inside
 *     padded unions, so a library configured with more of them than the headers we compiled
 *     against (e.g. 4.2 headers, 4.4 library) writes into our memory, never past it.
 *   - Embree 4's argument structs end with fields that only some library configurations have
 *     (RTC_MIN_WIDTH's minWidthDistanceFactor): they too sit in zeroed padded unions, so such a
 *     library reads the field's default (0) rather than stack garbage. Embree 3's intersect
 *     context has no such tail; its headers and library always come from one install.
 *
 * Errors: Embree reports an error on the thread whose API call failed, through the device's
 * callback, and also keeps a per-thread sticky code (rtcGetDeviceError) until it is read. The
 * shim keeps the callback's first error per thread as well, so concurrent builds on one shared
 * device never see each other's errors, and it reads Embree's sticky code whenever it takes an
 * error, so a failure never leaks into the next build on the same thread.
 */
#include "shim.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <sys/types.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if GLINT_EMBREE_MAJOR == 4
#include <embree4/rtcore.h>
#elif GLINT_EMBREE_MAJOR == 3
#include <embree3/rtcore.h>
#else
#error "GLINT_EMBREE_MAJOR must be 3 or 4 (set by build.rs)"
#endif

#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__)
#include <pmmintrin.h>
#include <xmmintrin.h>
#define GLINT_X86 1
#endif

/* Room, per ray, for hit fields a differently configured library writes past our headers' hit
 * struct: instID and instPrimID for up to 64 instance levels (8 bytes a level). */
#define GLINT_HIT_SLACK 512
/* Room for argument fields a differently configured library reads past our headers' struct. */
#define GLINT_ARGS_SLACK 64

/* The scene flag that lets a query's own filter run (glint_all_hits1). */
#if GLINT_EMBREE_MAJOR == 4
#define GLINT_SCENE_QUERY_FILTER_FLAG RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS
#else
#define GLINT_SCENE_QUERY_FILTER_FLAG RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION
#endif

struct glint_device {
    RTCDevice device;
};

struct glint_scene {
    RTCScene scene;
    /* The Embree device itself, retained: glint_device may be freed before its scenes. */
    RTCDevice device;
};

/* The first error Embree raised on this thread since the shim last took it. */
typedef struct error_slot {
    const glint_device *device; /* the device whose callback reported it */
    int code;                   /* an RTCError; 0 when the slot is empty */
    char message[512];
} error_slot;

static _Atomic int64_t live_handles = 0;
static _Atomic int64_t memory_bytes = 0;
static _Thread_local char creation_error[256];
static _Thread_local error_slot thread_error;

int glint_embree_major(void) { return GLINT_EMBREE_MAJOR; }

const char *glint_embree_version(void) { return RTC_VERSION_STRING; }

int64_t glint_live_handles(void) { return atomic_load(&live_handles); }

int64_t glint_memory_bytes(void) { return atomic_load(&memory_bytes); }

/* Embree reports every allocation (bytes > 0, before it happens) and release (bytes < 0, after);
 * glint only counts them and never refuses one. */
static bool on_memory(void *user, ssize_t bytes, bool post) {
    (void)user;
    (void)post;
    atomic_fetch_add(&memory_bytes, (int64_t)bytes);
    return true;
}

void glint_set_denormal_modes(void) {
#ifdef GLINT_X86
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
#endif
}

/* Embree calls this on the thread whose API call failed; user is the glint_device, used only
 * as a tag. */
static void on_error(void *user, enum RTCError code, const char *message) {
    if (code == RTC_ERROR_NONE || thread_error.code != 0) {
        return; /* keep the first error: later ones are usually its consequences */
    }
    thread_error.device = (const glint_device *)user;
    thread_error.code = (int)code;
    snprintf(thread_error.message, sizeof thread_error.message, "%s", message ? message : "");
}

glint_device *glint_device_new(const char *config) {
    glint_device *d = (glint_device *)calloc(1, sizeof *d);
    if (d == NULL) {
        snprintf(creation_error, sizeof creation_error, "out of memory");
        return NULL;
    }
    d->device = rtcNewDevice(config);
    if (d->device == NULL) {
        snprintf(creation_error, sizeof creation_error, "rtcNewDevice failed (error %d)",
                 (int)rtcGetDeviceError(NULL));
        free(d);
        return NULL;
    }
    rtcSetDeviceErrorFunction(d->device, on_error, d);
    rtcSetDeviceMemoryMonitorFunction(d->device, on_memory, NULL);
    atomic_fetch_add(&live_handles, 1);
    return d;
}

const char *glint_last_creation_error(void) { return creation_error; }

int glint_device_native_packet_width(const glint_device *d) {
    if (rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) {
        return 16;
    }
    if (rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) {
        return 8;
    }
    if (rtcGetDeviceProperty(d->device, RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED)) {
        return 4;
    }
    return 1;
}

void glint_device_free(glint_device *d) {
    if (d == NULL) {
        return;
    }
    /* Scenes still alive hold their own RTCDevice reference; the callback is removed so a late
     * error is never tagged with this freed handle. */
    rtcSetDeviceErrorFunction(d->device, NULL, NULL);
    rtcSetDeviceMemoryMonitorFunction(d->device, NULL, NULL);
    rtcReleaseDevice(d->device);
    free(d);
    atomic_fetch_sub(&live_handles, 1);
}

int glint_device_take_error(glint_device *d, char *buf, size_t len) {
    /* Reading Embree's sticky per-thread code clears it; it is the same error the callback saw
     * (or, with no callback match, one nobody asked for), so it is dropped either way. */
    int sticky = (int)rtcGetDeviceError(d->device);
    int code = thread_error.device == d ? thread_error.code : 0;
    if (code == 0) {
        code = sticky; /* an error raised without the callback installed */
    }
    if (buf != NULL && len > 0) {
        snprintf(buf, len, "%s",
                 thread_error.device == d ? thread_error.message
                 : code != 0              ? "(no message: another device's error was pending)"
                                          : "");
    }
    if (thread_error.device == d) {
        thread_error.device = NULL;
        thread_error.code = 0;
        thread_error.message[0] = '\0';
    }
    return code;
}

glint_scene *glint_scene_new(glint_device *d, glint_build_quality quality, int robust) {
    glint_scene *s = (glint_scene *)calloc(1, sizeof *s);
    if (s == NULL) {
        return NULL;
    }
    s->scene = rtcNewScene(d->device);
    if (s->scene == NULL) {
        free(s);
        return NULL;
    }
    rtcRetainDevice(d->device);
    s->device = d->device;
    enum RTCBuildQuality q = quality == GLINT_BUILD_LOW    ? RTC_BUILD_QUALITY_LOW
                             : quality == GLINT_BUILD_HIGH ? RTC_BUILD_QUALITY_HIGH
                                                           : RTC_BUILD_QUALITY_MEDIUM;
    rtcSetSceneBuildQuality(s->scene, q);
    /* Every scene accepts a filter passed with a query, so that glint_all_hits1 can collect
     * each hit a ray pierces; queries that pass none (all the others) run as before. */
    int flags = GLINT_SCENE_QUERY_FILTER_FLAG;
    if (robust) {
        flags |= RTC_SCENE_FLAG_ROBUST;
    }
    rtcSetSceneFlags(s->scene, (enum RTCSceneFlags)flags);
    atomic_fetch_add(&live_handles, 1);
    return s;
}

int64_t glint_scene_add_triangles(glint_scene *s, const float *positions, size_t vertex_count,
                                  const uint32_t *indices, size_t triangle_count) {
    RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (g == NULL) {
        return -1;
    }
    atomic_fetch_add(&live_handles, 1);
    float *v = (float *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                3 * sizeof(float), vertex_count);
    uint32_t *t = (uint32_t *)rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                      RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                                      triangle_count);
    /* Embree returns NULL for a buffer of zero items without raising an error; a mesh with no
     * triangles is valid and still takes a geometry id, so ids stay equal to mesh indices. */
    int buffers_ok = (v != NULL || vertex_count == 0) && (t != NULL || triangle_count == 0);
    int64_t id = -1;
    if (buffers_ok) {
        if (vertex_count > 0) {
            memcpy(v, positions, vertex_count * 3 * sizeof(float));
        }
        if (triangle_count > 0) {
            memcpy(t, indices, triangle_count * 3 * sizeof(uint32_t));
        }
        rtcCommitGeometry(g);
        unsigned attached = rtcAttachGeometry(s->scene, g);
        id = attached == RTC_INVALID_GEOMETRY_ID ? -1 : (int64_t)attached;
    }
    /* The scene holds its own reference once attached. */
    rtcReleaseGeometry(g);
    atomic_fetch_sub(&live_handles, 1);
    return id;
}

int64_t glint_scene_add_instance(glint_scene *s, const glint_scene *child, const float *xfm) {
    RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_INSTANCE);
    if (g == NULL) {
        return -1;
    }
    atomic_fetch_add(&live_handles, 1);
    rtcSetGeometryInstancedScene(g, child->scene);
    rtcSetGeometryTimeStepCount(g, 1);
    rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(g);
    unsigned attached = rtcAttachGeometry(s->scene, g);
    int64_t id = attached == RTC_INVALID_GEOMETRY_ID ? -1 : (int64_t)attached;
    rtcReleaseGeometry(g);
    atomic_fetch_sub(&live_handles, 1);
    return id;
}

int glint_scene_commit(glint_scene *s) {
    /* Embree's per-thread error code is sticky until read: clear whatever an earlier call left
     * so the code read below is this commit's own. */
    (void)rtcGetDeviceError(s->device);
    rtcCommitScene(s->scene);
    return (int)rtcGetDeviceError(s->device);
}

void glint_scene_free(glint_scene *s) {
    if (s == NULL) {
        return;
    }
    rtcReleaseScene(s->scene);
    rtcReleaseDevice(s->device);
    free(s);
    atomic_fetch_sub(&live_handles, 1);
}

/* ---- single rays ------------------------------------------------------------------------ */

typedef union {
    struct RTCRayHit rh;
    char slack[sizeof(struct RTCRayHit) + GLINT_HIT_SLACK];
} padded_rayhit;

typedef union {
    struct RTCRay8 r;
    char slack[sizeof(struct RTCRay8) + GLINT_HIT_SLACK];
} padded_ray8;

typedef union {
    struct RTCRayHit8 rh;
    char slack[sizeof(struct RTCRayHit8) + 8 * GLINT_HIT_SLACK];
} padded_rayhit8;

static void load_ray(struct RTCRay *r, const glint_ray *in) {
    r->org_x = in->org[0];
    r->org_y = in->org[1];
    r->org_z = in->org[2];
    r->tnear = in->tnear;
    r->dir_x = in->dir[0];
    r->dir_y = in->dir[1];
    r->dir_z = in->dir[2];
    r->time = 0.0f;
    r->tfar = in->tfar;
    r->mask = 0xFFFFFFFFu;
    r->id = 0;
    r->flags = 0;
}

/* GLINT_QUERY_ARGS declares `name`, a pointer to the per-call query arguments (Embree 4) or
 * intersect context (Embree 3) with the coherence hint set; the GLINT_* calls pass it in the
 * version's argument order. */
#if GLINT_EMBREE_MAJOR == 4
#define GLINT_QUERY_ARGS(name, kind, coherent)                                                   \
    union {                                                                                      \
        struct RTC##kind##Arguments args;                                                        \
        char slack[sizeof(struct RTC##kind##Arguments) + GLINT_ARGS_SLACK];                      \
    } name##_storage;                                                                            \
    memset(&name##_storage, 0, sizeof name##_storage);                                           \
    struct RTC##kind##Arguments *name = &name##_storage.args;                                    \
    rtcInit##kind##Arguments(name);                                                              \
    name->flags = (coherent) ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT
#define GLINT_INTERSECT1(scene, rh, args) rtcIntersect1((scene), (rh), (args))
#define GLINT_OCCLUDED1(scene, r, args) rtcOccluded1((scene), (r), (args))
#define GLINT_INTERSECT8(valid, scene, rh, args) rtcIntersect8((valid), (scene), (rh), (args))
#define GLINT_OCCLUDED8(valid, scene, r, args) rtcOccluded8((valid), (scene), (r), (args))
#else
#define GLINT_QUERY_ARGS(name, kind, coherent)                                                   \
    struct RTCIntersectContext name##_storage;                                                   \
    struct RTCIntersectContext *name = &name##_storage;                                          \
    rtcInitIntersectContext(name);                                                               \
    name->flags = (coherent) ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT                               \
                             : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
#define GLINT_INTERSECT1(scene, rh, args) rtcIntersect1((scene), (args), (rh))
#define GLINT_OCCLUDED1(scene, r, args) rtcOccluded1((scene), (args), (r))
#define GLINT_INTERSECT8(valid, scene, rh, args) rtcIntersect8((valid), (scene), (args), (rh))
#define GLINT_OCCLUDED8(valid, scene, r, args) rtcOccluded8((valid), (scene), (args), (r))
#endif

void glint_intersect1(const glint_scene *s, const glint_ray *rays, glint_hit *hits, size_t n,
                      int coherent) {
    GLINT_QUERY_ARGS(args, Intersect, coherent);
    padded_rayhit p;
    for (size_t i = 0; i < n; ++i) {
        load_ray(&p.rh.ray, &rays[i]);
        /* Embree requires geomID and instID[0] invalid on entry. */
        p.rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        p.rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        p.rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        GLINT_INTERSECT1(s->scene, &p.rh, args);
        glint_hit *h = &hits[i];
        h->geom_id = p.rh.hit.geomID;
        h->prim_id = p.rh.hit.primID;
        h->inst_id = p.rh.hit.instID[0];
        h->t = p.rh.ray.tfar;
        h->u = p.rh.hit.u;
        h->v = p.rh.hit.v;
        h->ng[0] = p.rh.hit.Ng_x;
        h->ng[1] = p.rh.hit.Ng_y;
        h->ng[2] = p.rh.hit.Ng_z;
    }
}

void glint_occluded1(const glint_scene *s, const glint_ray *rays, uint8_t *occluded, size_t n,
                     int coherent) {
    GLINT_QUERY_ARGS(args, Occluded, coherent);
    struct RTCRay r;
    for (size_t i = 0; i < n; ++i) {
        load_ray(&r, &rays[i]);
        GLINT_OCCLUDED1(s->scene, &r, args);
        /* Embree marks an occluded ray by setting tfar to -inf. */
        occluded[i] = r.tfar < 0.0f && isinf(r.tfar);
    }
}

/* ---- packets of 8 ----------------------------------------------------------------------- */

static void load_ray8(struct RTCRay8 *r, const glint_ray *in, size_t count, int *valid) {
    for (size_t k = 0; k < 8; ++k) {
        /* Lanes past the end repeat the last ray and are masked off. */
        const glint_ray *src = &in[k < count ? k : count - 1];
        valid[k] = k < count ? -1 : 0;
        r->org_x[k] = src->org[0];
        r->org_y[k] = src->org[1];
        r->org_z[k] = src->org[2];
        r->tnear[k] = src->tnear;
        r->dir_x[k] = src->dir[0];
        r->dir_y[k] = src->dir[1];
        r->dir_z[k] = src->dir[2];
        r->time[k] = 0.0f;
        r->tfar[k] = src->tfar;
        r->mask[k] = 0xFFFFFFFFu;
        r->id[k] = (unsigned)k;
        r->flags[k] = 0;
    }
}

void glint_intersect8(const glint_scene *s, const glint_ray *rays, glint_hit *hits, size_t n,
                      int coherent) {
    GLINT_QUERY_ARGS(args, Intersect, coherent);
    padded_rayhit8 p __attribute__((aligned(64)));
    int valid[8] __attribute__((aligned(32)));
    for (size_t base = 0; base < n; base += 8) {
        size_t count = n - base < 8 ? n - base : 8;
        load_ray8(&p.rh.ray, rays + base, count, valid);
        for (size_t k = 0; k < 8; ++k) {
            p.rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
            p.rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
            p.rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        GLINT_INTERSECT8(valid, s->scene, &p.rh, args);
        for (size_t k = 0; k < count; ++k) {
            glint_hit *h = &hits[base + k];
            h->geom_id = p.rh.hit.geomID[k];
            h->prim_id = p.rh.hit.primID[k];
            h->inst_id = p.rh.hit.instID[0][k];
            h->t = p.rh.ray.tfar[k];
            h->u = p.rh.hit.u[k];
            h->v = p.rh.hit.v[k];
            h->ng[0] = p.rh.hit.Ng_x[k];
            h->ng[1] = p.rh.hit.Ng_y[k];
            h->ng[2] = p.rh.hit.Ng_z[k];
        }
    }
}

void glint_occluded8(const glint_scene *s, const glint_ray *rays, uint8_t *occluded, size_t n,
                     int coherent) {
    GLINT_QUERY_ARGS(args, Occluded, coherent);
    padded_ray8 p __attribute__((aligned(64)));
    int valid[8] __attribute__((aligned(32)));
    for (size_t base = 0; base < n; base += 8) {
        size_t count = n - base < 8 ? n - base : 8;
        load_ray8(&p.r, rays + base, count, valid);
        GLINT_OCCLUDED8(valid, s->scene, &p.r, args);
        for (size_t k = 0; k < count; ++k) {
            occluded[base + k] = p.r.tfar[k] < 0.0f && isinf(p.r.tfar[k]);
        }
    }
}

/* ---- every hit along a ray -------------------------------------------------------------- */

/* The query context glint_all_hits1 passes: Embree's own context first (padded, as a library
 * configured with more instance levels writes past our headers' struct), then where the
 * filter puts the hits. The filter receives a pointer to the first member, so it can reach
 * the rest. */
#if GLINT_EMBREE_MAJOR == 4
typedef struct RTCRayQueryContext glint_embree_context;
#else
typedef struct RTCIntersectContext glint_embree_context;
#endif

typedef struct all_hits_context {
    union {
        glint_embree_context base;
        char slack[sizeof(glint_embree_context) + GLINT_HIT_SLACK];
    } embree;
    glint_hit *hits;
    size_t capacity;
    size_t count;
} all_hits_context;

/* Embree's hit and ray packets are structs of arrays; its accessors (RTCHitN_u, ...) are C++
 * only, so these read the same slots: the hit's Ng_x, Ng_y, Ng_z, u, v, primID, geomID, then
 * instID per level, N lanes each; the ray's tfar after 8 other arrays. */
#define GLINT_HITN_F(hit, n, i, slot) (((const float *)(const void *)(hit))[(slot) * (n) + (i)])
#define GLINT_HITN_U(hit, n, i, slot) (((const unsigned *)(const void *)(hit))[(slot) * (n) + (i)])

/* Records every candidate hit and rejects it, so that traversal goes on to the next. */
static void collect_every_hit(const struct RTCFilterFunctionNArguments *args) {
    all_hits_context *c = (all_hits_context *)(void *)args->context;
    unsigned n = args->N;
    for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] == 0) {
            continue;
        }
        if (c->count < c->capacity) {
            glint_hit *h = &c->hits[c->count];
            h->t = ((const float *)(const void *)args->ray)[8 * n + i];
            h->ng[0] = GLINT_HITN_F(args->hit, n, i, 0);
            h->ng[1] = GLINT_HITN_F(args->hit, n, i, 1);
            h->ng[2] = GLINT_HITN_F(args->hit, n, i, 2);
            h->u = GLINT_HITN_F(args->hit, n, i, 3);
            h->v = GLINT_HITN_F(args->hit, n, i, 4);
            h->prim_id = GLINT_HITN_U(args->hit, n, i, 5);
            h->geom_id = GLINT_HITN_U(args->hit, n, i, 6);
            h->inst_id = GLINT_HITN_U(args->hit, n, i, 7);
        }
        c->count += 1;
        args->valid[i] = 0;
    }
}

size_t glint_all_hits1(const glint_scene *s, const glint_ray *ray, glint_hit *hits,
                       size_t capacity) {
    all_hits_context c;
    memset(&c, 0, sizeof c);
    c.hits = hits;
    c.capacity = capacity;
    padded_rayhit p;
    load_ray(&p.rh.ray, ray);
    p.rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    p.rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    p.rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if GLINT_EMBREE_MAJOR == 4
    rtcInitRayQueryContext(&c.embree.base);
    GLINT_QUERY_ARGS(args, Intersect, 0);
    args->context = &c.embree.base;
    args->filter = collect_every_hit;
    args->flags |= RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER;
    rtcIntersect1(s->scene, &p.rh, args);
#else
    rtcInitIntersectContext(&c.embree.base);
    c.embree.base.filter = collect_every_hit;
    rtcIntersect1(s->scene, &c.embree.base, &p.rh);
#endif
    return c.count;
}
