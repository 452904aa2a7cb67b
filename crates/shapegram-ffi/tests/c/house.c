/* The C ABI from C: derives examples/house.cga, checks the buffers' counts against those the
 * Rust API gives (passed as arguments by tests/c.rs), then the errors; then the rule package
 * examples/town.rpk, from its file and from its bytes, and packages that cannot be used. Run
 * under valgrind by .ci/run, so that a leak fails CI.
 *
 * usage: house GRAMMAR VERTICES INDICES PARTS VERTICES3 INDICES3 PARTS3 PACKAGE PVERTICES
 *        PINDICES PPARTS COMPILED_ONLY
 * (the counts of seed 0, then of seed 7 with storeys = 3, then of the package; COMPILED_ONLY
 * is a package of compiled rules alone). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shapegram.h"

static int failures = 0;

#define CHECK(condition)                                                     \
    do {                                                                     \
        if (!(condition)) {                                                  \
            fprintf(stderr, "%s:%d: failed: %s\n", __FILE__, __LINE__,       \
                    #condition);                                             \
            failures++;                                                      \
        }                                                                    \
    } while (0)

/* Derives and checks the counts, and that every index is a vertex and every part lies
 * inside the buffers. */
static void derive_and_check(sg_state *state, size_t vertices, size_t indices,
                             size_t parts) {
    CHECK(sg_state_derive(state) == SG_OK);
    CHECK(strcmp(sg_state_last_error(state), "") == 0);
    sg_mesh mesh;
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    printf("derived: %zu vertices, %zu indices, %zu parts\n", mesh.vertex_count,
           mesh.index_count, mesh.part_count);
    CHECK(mesh.vertex_count == vertices);
    CHECK(mesh.index_count == indices);
    CHECK(mesh.part_count == parts);
    CHECK(mesh.index_count % 3 == 0);
    for (size_t i = 0; i < mesh.index_count; i++) {
        if (mesh.indices[i] >= mesh.vertex_count) {
            CHECK(mesh.indices[i] < mesh.vertex_count);
            break;
        }
    }
    size_t covered = 0;
    for (size_t p = 0; p < mesh.part_count; p++) {
        const sg_part *part = &mesh.parts[p];
        CHECK(part->first_vertex + part->vertex_count <= mesh.vertex_count);
        CHECK(part->first_index == covered);
        CHECK(part->color[3] > 0.0f && part->color[3] <= 1.0f);
        CHECK(part->name != NULL && part->name[0] != '\0');
        covered += part->index_count;
    }
    CHECK(covered == mesh.index_count);
    /* Normals are unit vectors. */
    for (size_t v = 0; v < mesh.vertex_count; v++) {
        const float *n = &mesh.normals[3 * v];
        float length = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if (length < 0.99f || length > 1.01f) {
            CHECK(length >= 0.99f && length <= 1.01f);
            break;
        }
    }
}

/* The bytes of the file at `path` (malloc'ed; NULL when it cannot be read). */
static unsigned char *read_file(const char *path, size_t *size) {
    FILE *file = fopen(path, "rb");
    if (!file) return NULL;
    unsigned char *bytes = NULL;
    if (fseek(file, 0, SEEK_END) == 0) {
        long length = ftell(file);
        if (length >= 0 && fseek(file, 0, SEEK_SET) == 0) {
            bytes = malloc((size_t)length + 1);
            if (bytes && fread(bytes, 1, (size_t)length, file) != (size_t)length) {
                free(bytes);
                bytes = NULL;
            }
            *size = (size_t)length;
        }
    }
    fclose(file);
    return bytes;
}

/* A rule package from its file (named and not), from its bytes, another rule file of it, and
 * packages that cannot be used. */
static void check_packages(sg_state *state, const char *package, const size_t counts[3],
                           const char *compiled_only) {
    CHECK(sg_state_load_package_file(state, package, NULL) == SG_OK);
    derive_and_check(state, counts[0], counts[1], counts[2]);
    sg_mesh mesh;
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    /* The brick texture comes from inside the package. */
    CHECK(mesh.texture_count == 1);
    sg_texture texture;
    CHECK(sg_state_texture(state, 0, &texture) == SG_OK);
    CHECK(strcmp(texture.path, "brick.png") == 0);
    CHECK(texture.size > 8 && memcmp(texture.data, "\x89PNG", 4) == 0);
    /* Its attributes: a higher mass, the same count of triangles. */
    CHECK(sg_state_set_number(state, "height", 20) == SG_OK);
    derive_and_check(state, counts[0], counts[1], counts[2]);
    CHECK(sg_state_set_string(state, "height", "tall") == SG_ATTRIBUTE_TYPE);
    CHECK(strstr(sg_state_last_error(state), "town.rpk!/rules/town.cga:10:6: ") != NULL);

    /* The same through sg_state_load_file, and by the rule file's name. */
    CHECK(sg_state_load_file(state, package, SG_KIND_AUTO) == SG_OK);
    derive_and_check(state, counts[0], counts[1], counts[2]);
    CHECK(sg_state_load_package_file(state, package, "town.cga") == SG_OK);
    derive_and_check(state, counts[0], counts[1], counts[2]);

    /* From its bytes. */
    size_t size = 0;
    unsigned char *bytes = read_file(package, &size);
    CHECK(bytes != NULL);
    if (bytes) {
        CHECK(sg_state_load_package_bytes(state, bytes, size, "town.rpk", NULL) == SG_OK);
        derive_and_check(state, counts[0], counts[1], counts[2]);
        /* A damaged copy: its second half cut off. */
        CHECK(sg_state_load_package_bytes(state, bytes, size / 2, "cut.rpk", NULL) ==
              SG_PACKAGE_ERROR);
        printf("cut package: %s\n", sg_state_last_error(state));
        CHECK(strncmp(sg_state_last_error(state),
                      "cut.rpk is not a readable rule package (a 7-Zip archive): ", 58) == 0);
        free(bytes);
    }
    /* The failed loads kept the package loaded. */
    derive_and_check(state, counts[0], counts[1], counts[2]);

    /* A rule file the package lacks: the message lists those it has. */
    CHECK(sg_state_load_package_file(state, package, "nope.cga") == SG_PACKAGE_ERROR);
    CHECK(strstr(sg_state_last_error(state),
                 "has no rule file `nope.cga`; its rule files are rules/town.cga") != NULL);
    /* Not an archive, compiled rules only, no file, NULL. */
    const char *text = "Lot --> X.";
    CHECK(sg_state_load_package_bytes(state, (const unsigned char *)text, strlen(text), NULL,
                                      NULL) == SG_PACKAGE_ERROR);
    CHECK(strncmp(sg_state_last_error(state), "package.rpk is not a readable rule package", 42) ==
          0);
    CHECK(sg_state_load_package_file(state, compiled_only, NULL) == SG_PACKAGE_ERROR);
    CHECK(strstr(sg_state_last_error(state),
                 "holds only compiled rules (bin/main.cgb) and no CGA source") != NULL);
    CHECK(sg_state_load_package_file(state, "/nonexistent/town.rpk", NULL) == SG_IO);
    CHECK(sg_state_load_package_file(state, NULL, NULL) == SG_NULL_ARGUMENT);
    CHECK(sg_state_load_package_bytes(state, NULL, 4, NULL, NULL) == SG_NULL_ARGUMENT);
    CHECK(sg_state_load_package_bytes(state, NULL, 0, NULL, NULL) == SG_PACKAGE_ERROR);
}

int main(int argc, char **argv) {
    if (argc != 13) {
        fprintf(stderr, "usage: house GRAMMAR V I P V3 I3 P3 PACKAGE PV PI PP COMPILED_ONLY\n");
        return 2;
    }
    size_t counts[6];
    for (int i = 0; i < 6; i++) counts[i] = strtoull(argv[2 + i], NULL, 10);
    size_t package_counts[3];
    for (int i = 0; i < 3; i++) package_counts[i] = strtoull(argv[9 + i], NULL, 10);

    sg_state *state = sg_state_new();
    CHECK(state != NULL);

    /* Nothing loaded yet. */
    CHECK(sg_state_derive(state) == SG_NO_GRAMMAR);
    CHECK(strcmp(sg_state_last_error(state), "no grammar is loaded") == 0);

    CHECK(sg_state_load_file(state, argv[1], SG_KIND_AUTO) == SG_OK);
    derive_and_check(state, counts[0], counts[1], counts[2]);

    /* Another seed and another attribute value. */
    CHECK(sg_state_set_seed(state, 7) == SG_OK);
    CHECK(sg_state_set_number(state, "storeys", 3) == SG_OK);
    derive_and_check(state, counts[3], counts[4], counts[5]);

    /* Attributes of the wrong type or name. */
    CHECK(sg_state_set_string(state, "storeys", "three") == SG_ATTRIBUTE_TYPE);
    CHECK(strstr(sg_state_last_error(state),
                 "house.cga:8:6: the attribute `storeys` is a number, not a string") != NULL);
    CHECK(sg_state_set_bool(state, "wallColor", true) == SG_ATTRIBUTE_TYPE);
    CHECK(sg_state_set_string(state, "wallColor", "#ffffff") == SG_OK);
    CHECK(sg_state_set_number(state, "storys", 2) == SG_UNKNOWN_ATTRIBUTE);
    CHECK(strstr(sg_state_last_error(state), "did you mean `storeys`?") != NULL);

    /* Null pointers and bad UTF-8. */
    sg_mesh mesh;
    CHECK(sg_state_derive(NULL) == SG_NULL_ARGUMENT);
    CHECK(strcmp(sg_state_last_error(NULL), "the handle is NULL") == 0);
    CHECK(sg_state_mesh(state, NULL) == SG_NULL_ARGUMENT);
    CHECK(sg_state_load_text(state, NULL, SG_KIND_CGA, NULL) == SG_NULL_ARGUMENT);
    CHECK(strcmp(sg_state_last_error(state), "the grammar text is NULL") == 0);
    CHECK(sg_state_set_number(state, NULL, 1) == SG_NULL_ARGUMENT);
    CHECK(sg_state_add_lot(state, NULL, 4) == SG_NULL_ARGUMENT);
    CHECK(sg_state_load_text(state, "Lot --> \xff\xfe", SG_KIND_CGA, NULL) ==
          SG_INVALID_UTF8);
    CHECK(strcmp(sg_state_last_error(state),
                 "the grammar text is not UTF-8 (invalid byte at offset 8)") == 0);
    CHECK(sg_state_load_text(state, "Lot --> X", 99, NULL) == SG_INVALID_ARGUMENT);
    CHECK(sg_state_load_file(state, "/nonexistent/house.cga", SG_KIND_AUTO) == SG_IO);

    /* A grammar with an error: the message has its place; the old grammar stays. */
    CHECK(sg_state_load_text(state, "Lot -->\n  extrude(3) Mass\nMass --> color(\"#fff\" Wall\n",
                             SG_KIND_AUTO, "broken.cga") == SG_GRAMMAR_ERROR);
    const char *message = sg_state_last_error(state);
    printf("grammar error: %s\n", message);
    CHECK(strstr(message, "broken.cga:3:") != NULL);
    CHECK(sg_state_derive(state) == SG_OK);

    /* Lots: too few corners, then a 10 x 10 lot instead of the default. */
    const float square[] = {0, 0, 0, 10, 0, 0, 10, 0, 10, 0, 0, 10};
    CHECK(sg_state_add_lot(state, square, 2) == SG_INVALID_ARGUMENT);
    CHECK(sg_state_add_lot(state, square, 4) == SG_OK);
    CHECK(sg_state_derive(state) == SG_OK);
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    CHECK(mesh.vertex_count > 0);
    for (size_t v = 0; v < mesh.vertex_count; v++) {
        const float *p = &mesh.positions[3 * v];
        /* The roof overhangs the lot; the default 20 x 30 lot would reach z = 30. */
        if (p[0] < -3.0f || p[0] > 13.0f || p[2] < -3.0f || p[2] > 13.0f) {
            CHECK(!"a vertex far outside the 10 x 10 lot");
            break;
        }
    }

    /* A derivation that fails is an error with a message, and leaves no buffers. */
    CHECK(sg_state_load_text(state, "attr n = 1\nLot --> X\nX --> X\n", SG_KIND_CGA,
                             "endless.cga") == SG_OK);
    CHECK(sg_state_derive(state) == SG_DERIVE_ERROR);
    printf("derive error: %s\n", sg_state_last_error(state));
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    CHECK(mesh.vertex_count == 0 && mesh.part_count == 0);

    /* A textured grammar (beside the house): uvs for every vertex, each image once. */
    char textured[4096];
    const char *slash = strrchr(argv[1], '/');
    int folder = slash ? (int)(slash - argv[1] + 1) : 0;
    snprintf(textured, sizeof textured, "%.*stextured_house.cga", folder, argv[1]);
    CHECK(sg_state_load_file(state, textured, SG_KIND_AUTO) == SG_OK);
    CHECK(sg_state_derive(state) == SG_OK);
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    CHECK(mesh.uvs != NULL);
    CHECK(mesh.texture_count == 2);
    size_t textured_parts = 0;
    for (size_t p = 0; p < mesh.part_count; p++) {
        CHECK(mesh.parts[p].texture >= -1 && mesh.parts[p].texture < (int)mesh.texture_count);
        textured_parts += mesh.parts[p].texture >= 0;
    }
    CHECK(textured_parts == 2);
    /* The textured parts are named as the grammar names their materials; the others are not. */
    for (size_t p = 0; p < mesh.part_count; p++) {
        const char *material = mesh.parts[p].material;
        if (mesh.parts[p].texture < 0) {
            CHECK(material == NULL);
        } else {
            CHECK(material != NULL &&
                  (strcmp(material, "brick") == 0 || strcmp(material, "roof_tiles") == 0));
        }
    }
    sg_texture texture;
    CHECK(sg_state_texture(state, 0, &texture) == SG_OK);
    CHECK(strcmp(texture.path, "textures/brick.png") == 0);
    CHECK(texture.size > 8 && memcmp(texture.data, "\x89PNG", 4) == 0);
    CHECK(sg_state_texture(state, 2, &texture) == SG_INVALID_ARGUMENT);
    CHECK(strcmp(sg_state_last_error(state), "texture 2: the buffers have 2") == 0);
    CHECK(sg_state_texture(state, 0, NULL) == SG_NULL_ARGUMENT);

    /* The excavator (beside the house): its skeleton's joints, and each vertex's joint. */
    char excavator[4096];
    snprintf(excavator, sizeof excavator, "%.*sexcavator.cga", folder, argv[1]);
    CHECK(sg_state_load_file(state, excavator, SG_KIND_AUTO) == SG_OK);
    CHECK(sg_state_set_number(state, "boomAngle", 45) == SG_OK);
    CHECK(sg_state_derive(state) == SG_OK);
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    CHECK(mesh.joints != NULL && mesh.joint_count > 3);
    CHECK(mesh.vertex_joints != NULL);
    CHECK(mesh.joints[0].parent == -1);
    const sg_joint *boom = NULL;
    for (size_t j = 0; j < mesh.joint_count; j++) {
        CHECK(mesh.joints[j].parent < (int32_t)j);
        if (strncmp(mesh.joints[j].name, "Boom_", 5) == 0) boom = &mesh.joints[j];
    }
    CHECK(boom != NULL);
    if (boom) {
        CHECK(boom->pose_rotation_deg[2] == 45.0f);
        CHECK(boom->rotation_limits_deg[2][0] == -40.0f && boom->rotation_limits_deg[2][1] == 60.0f);
    }
    size_t on_boom = 0;
    for (size_t v = 0; v < mesh.vertex_count; v++) {
        CHECK(mesh.vertex_joints[v] < mesh.joint_count);
        on_boom += boom && &mesh.joints[mesh.vertex_joints[v]] == boom;
    }
    CHECK(on_boom > 0);
    printf("excavator: %zu joints, %zu of %zu vertices on the boom\n", mesh.joint_count, on_boom,
           mesh.vertex_count);
    /* The house has no skeleton. */
    CHECK(sg_state_load_file(state, argv[1], SG_KIND_AUTO) == SG_OK);
    CHECK(sg_state_derive(state) == SG_OK);
    CHECK(sg_state_mesh(state, &mesh) == SG_OK);
    CHECK(mesh.joints == NULL && mesh.joint_count == 0 && mesh.vertex_joints == NULL);

    check_packages(state, argv[8], package_counts, argv[12]);

    uint64_t applications = 1;
    CHECK(sg_state_progress(state, &applications) == SG_OK);
    CHECK(sg_state_progress(state, NULL) == SG_NULL_ARGUMENT);
    CHECK(sg_state_cancel(NULL) == SG_NULL_ARGUMENT);

    CHECK(sg_state_free(state) == SG_OK);
    CHECK(sg_state_free(NULL) == SG_OK);
    if (failures) {
        fprintf(stderr, "%d checks failed\n", failures);
        return 1;
    }
    printf("all checks passed\n");
    return 0;
}
