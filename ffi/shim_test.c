/*
 * Tests of the shim's contract that Rust cannot reach, run against a real Embree 3 or 4 by
 * scripts/check-embree4.sh:
 *   - the library's runtime version against the headers the shim was compiled with;
 *   - how many bytes past our headers' RTCRayHit / RTCRayHit8 the library writes (instPrimID,
 *     instance levels), which must fit in the padded unions (GLINT_HIT_SLACK);
 *   - occlusion's convention (tfar = -inf on a hit);
 *   - errors: taken once, per thread, never leaking into the next commit;
 *   - lifetimes: a scene outlives its freed device; the live-handle count returns to zero.
 *
 * It includes shim.c to see its private types and constants. Build (see the script):
 *   cc -std=c11 -DGLINT_EMBREE_MAJOR=4 -Iffi -isystem INCLUDE ffi/shim_test.c -lembree4 -lpthread
 * Exits 0 when every check passes, 1 otherwise; prints what it measured.
 */
#include "shim.c"

#include <pthread.h>

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

static void check_versions(glint_device *d) {
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
}

/* Fills the padded single-ray union with `fill`, traces the down ray and reports how far past
 * our struct RTCRayHit the library wrote. */
static size_t overrun1(glint_scene *s, unsigned char fill) {
    GLINT_QUERY_ARGS(args, Intersect, 0);
    padded_rayhit p;
    memset(&p, fill, sizeof p);
    glint_ray in = down_ray();
    load_ray(&p.rh.ray, &in);
    p.rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    p.rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    GLINT_INTERSECT1(s->scene, &p.rh, args);
    CHECK(p.rh.hit.geomID == 0 && p.rh.ray.tfar == 1.0f, "rtcIntersect1 missed (geomID %u, t %g)",
          p.rh.hit.geomID, (double)p.rh.ray.tfar);
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

static void check_struct_overruns(glint_scene *s) {
    /* Two fills, so a written byte that happens to equal one fill is still seen. */
    size_t a1 = overrun1(s, 0xA5), b1 = overrun1(s, 0x5A);
    size_t a8 = overrun8(s, 0xA5), b8 = overrun8(s, 0x5A);
    size_t past1 = a1 > b1 ? a1 : b1;
    size_t past8 = a8 > b8 ? a8 : b8;
    printf("rtcIntersect1 wrote %zu bytes past our struct RTCRayHit (%zu bytes); room %d\n", past1,
           sizeof(struct RTCRayHit), GLINT_HIT_SLACK);
    printf("rtcIntersect8 wrote %zu bytes past our struct RTCRayHit8 (%zu bytes); room %d\n", past8,
           sizeof(struct RTCRayHit8), 8 * GLINT_HIT_SLACK);
    CHECK(past1 <= GLINT_HIT_SLACK, "single-ray overrun %zu exceeds the slack", past1);
    CHECK(past8 <= 8 * GLINT_HIT_SLACK, "packet overrun %zu exceeds the slack", past8);
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

static void check_lifetimes(void) {
    int64_t before = glint_live_handles();
    glint_device *d = glint_device_new(NULL);
    CHECK(d != NULL, "device: %s", glint_last_creation_error());
    glint_scene *s = glint_scene_new(d, GLINT_BUILD_HIGH, 1);
    glint_device_free(d); /* before the scene is filled, built and used */
    CHECK(glint_scene_add_triangles(s, TRIANGLE, 3, TRIANGLE_INDICES, 1) == 0, "add failed");
    CHECK(glint_scene_commit(s) == 0, "commit failed");
    glint_ray r = down_ray();
    glint_hit h;
    glint_intersect1(s, &r, &h, 1, 1);
    CHECK(h.geom_id == 0 && h.t == 1.0f, "hit after the device was freed: geom %u t %g",
          h.geom_id, (double)h.t);
    glint_scene_free(s);
    CHECK(glint_live_handles() == before, "live handles %lld, expected %lld",
          (long long)glint_live_handles(), (long long)before);
}

int main(void) {
    glint_set_denormal_modes();
    glint_device *d = glint_device_new(NULL);
    if (d == NULL) {
        fprintf(stderr, "FAIL: no Embree device: %s\n", glint_last_creation_error());
        return 1;
    }
    check_versions(d);
    glint_scene *s = triangle_scene(d);
    CHECK(s != NULL, "the one-triangle scene did not build");
    if (s != NULL) {
        check_struct_overruns(s);
        check_occlusion_convention(s);
        glint_scene_free(s);
    }
    check_errors(d);
    glint_device_free(d);
    check_lifetimes();
    CHECK(glint_live_handles() == 0, "%lld handles leaked", (long long)glint_live_handles());
    printf("%s: %d failure(s)\n", failures == 0 ? "shim_test passed" : "shim_test FAILED",
           failures);
    return failures == 0 ? 0 : 1;
}
