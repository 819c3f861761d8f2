/*
 * glint's C ABI over Embree 3 and Embree 4.
 *
 * Rust binds this header (bindgen), never Embree's own headers: Embree's ray and hit structs
 * change size with the build options in its rtcore_config.h (instance levels, instPrimID), and
 * its argument-init helpers are inline functions with no symbol. Everything here is plain data
 * that glint owns; shim.c copies it into Embree's structs, which it compiles against the
 * installed headers, so the layouts always match the library's.
 */
#ifndef GLINT_SHIM_H
#define GLINT_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** A ray: origin, direction (need not be normalised) and the parametric interval [tnear, tfar]. */
typedef struct glint_ray {
    float org[3];
    float tnear;
    float dir[3];
    float tfar;
} glint_ray;

/** Sentinel for "no hit" in glint_hit.geom_id. */
#define GLINT_INVALID_ID 0xFFFFFFFFu

/**
 * The closest hit: t, Embree's barycentrics (u weights vertex 1, v weights vertex 2), the
 * unnormalised geometric normal as Embree reports it (in the hit geometry's object space when
 * an instance was hit), and the geometry and primitive ids. geom_id is GLINT_INVALID_ID on a
 * miss. inst_id is the instance geometry's id in the top-level scene when the hit is inside an
 * instance (geom_id then names the geometry inside the instanced scene), else GLINT_INVALID_ID.
 */
typedef struct glint_hit {
    float t;
    float u;
    float v;
    float ng[3];
    uint32_t geom_id;
    uint32_t prim_id;
    uint32_t inst_id;
} glint_hit;

/** Opaque handles. */
typedef struct glint_device glint_device;
typedef struct glint_scene glint_scene;

/** Build quality, as Embree's RTC_BUILD_QUALITY_{LOW,MEDIUM,HIGH}. */
typedef enum glint_build_quality {
    GLINT_BUILD_LOW = 0,
    GLINT_BUILD_MEDIUM = 1,
    GLINT_BUILD_HIGH = 2
} glint_build_quality;

/** The Embree major version this shim was compiled against (3 or 4). */
int glint_embree_major(void);

/** Embree's version string from the headers the shim was compiled against. */
const char *glint_embree_version(void);

/** Live device, scene and geometry handles created by this shim and not yet released. */
int64_t glint_live_handles(void);

/**
 * Sets flush-to-zero and denormals-are-zero on the calling thread, as Embree recommends for
 * every thread that traces rays. A no-op off x86.
 */
void glint_set_denormal_modes(void);

/** Creates a device (config may be NULL). Returns NULL on failure; see glint_last_creation_error. */
glint_device *glint_device_new(const char *config);

/**
 * The widest ray packet the device's kernels run natively: 16 (AVX-512), 8 (AVX, AVX2), 4 (SSE)
 * or 1. It tells which instruction set a device configured with isa=... really got (Embree
 * falls back to SSE2 silently on a name it does not know).
 */
int glint_device_native_packet_width(const glint_device *device);

/** The message of the last failed glint_device_new on this thread (static storage). */
const char *glint_last_creation_error(void);

/**
 * Releases a device. Scenes keep their own reference to the Embree device, so order does not
 * matter; errors those scenes raise later are no longer recorded (commit still returns its code).
 */
void glint_device_free(glint_device *device);

/**
 * Takes the first error Embree reported on this device to the calling thread since the last
 * call (0 if none), copies its message into buf (NUL-terminated, truncated to len) and clears
 * it, together with Embree's own sticky per-thread error code. Errors are kept per thread, as
 * Embree raises them, so threads building scenes at once never take each other's errors.
 */
int glint_device_take_error(glint_device *device, char *buf, size_t len);

/** Creates an empty scene; robust selects RTC_SCENE_FLAG_ROBUST. NULL on failure. */
glint_scene *glint_scene_new(glint_device *device, glint_build_quality quality, int robust);

/**
 * Adds a triangle mesh, copying its data into Embree-owned buffers.
 * positions: vertex_count * 3 floats; indices: triangle_count * 3 indices. Either count may be
 * 0 (the mesh still takes the next geometry id). Returns the geometry id, or -1 on error (the
 * device's error holds why).
 */
int64_t glint_scene_add_triangles(glint_scene *scene, const float *positions, size_t vertex_count,
                                  const uint32_t *indices, size_t triangle_count);

/**
 * Adds an instance of the committed scene child with the affine transform xfm (12 floats: the
 * 3x4 world-from-object matrix, column-major). child must outlive scene. Returns the geometry
 * id, or -1 on error (the device's error holds why).
 */
int64_t glint_scene_add_instance(glint_scene *scene, const glint_scene *child, const float *xfm);

/**
 * Bytes Embree currently holds for all devices the shim created, as its memory-monitor callback
 * reports them (for benchmarks; builds on other threads count too).
 */
int64_t glint_memory_bytes(void);

/**
 * Builds the acceleration structure. Returns 0 on success, otherwise the RTCError code the commit
 * itself raised (never one left over from an earlier call).
 */
int glint_scene_commit(glint_scene *scene);

/** Releases a scene and its geometries. */
void glint_scene_free(glint_scene *scene);

/** Closest hit for each of n rays, one at a time (rtcIntersect1). */
void glint_intersect1(const glint_scene *scene, const glint_ray *rays, glint_hit *hits, size_t n,
                      int coherent);

/** Closest hit for n rays in packets of 8 (rtcIntersect8); the last packet is masked. */
void glint_intersect8(const glint_scene *scene, const glint_ray *rays, glint_hit *hits, size_t n,
                      int coherent);

/** Any hit in [tnear, tfar] for each of n rays (rtcOccluded1): occluded[i] = 1 if blocked. */
void glint_occluded1(const glint_scene *scene, const glint_ray *rays, uint8_t *occluded, size_t n,
                     int coherent);

/** Any hit for n rays in packets of 8 (rtcOccluded8). */
void glint_occluded8(const glint_scene *scene, const glint_ray *rays, uint8_t *occluded, size_t n,
                     int coherent);

/**
 * Every hit of one ray in [tnear, tfar], in no particular order (rtcIntersect1 with a filter
 * that records each candidate and rejects it): writes up to capacity of them into hits and
 * returns how many there are (call again with more room when that exceeds capacity). A
 * triangle referenced from several leaves (spatial splits) may be listed more than once.
 * glint_hit's fields are as for glint_intersect1.
 */
size_t glint_all_hits1(const glint_scene *scene, const glint_ray *ray, glint_hit *hits,
                       size_t capacity);

#ifdef __cplusplus
}
#endif

#endif /* GLINT_SHIM_H */
