/* import_openmesh.h: private C interface to the C++17 OpenMesh adapter
 * (import_openmesh.cpp). import.c validates and canonicalises the file in
 * memory first, then hands the bytes here; OpenMesh's reader parses them into
 * a raw polygon soup (no manifoldness checks, nothing dropped by us).
 */
#ifndef SSS_IMPORT_OPENMESH_H
#define SSS_IMPORT_OPENMESH_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Which OpenMesh reader parses the bytes. */
typedef enum sss_om_format {
    SSS_OM_PLY = 0,        /* ascii or binary, decided by the header */
    SSS_OM_OBJ,
    SSS_OM_OFF,            /* ascii; the caller rewrites the header to plain "OFF" */
    SSS_OM_STL_ASCII,
    SSS_OM_STL_BINARY
} sss_om_format;

/* Polygon soup as the reader delivered it. Face f has fsize[f] vertex
 * indices, stored consecutively in idx (faces in order). Indices are
 * OpenMesh VertexHandle values: they may be negative or >= nv when the file
 * is bad; the caller checks. All arrays are malloc'd (or NULL when empty). */
typedef struct sss_om_soup {
    float *pos;        /* 3 * nv */
    uint64_t nv;
    int32_t *idx;      /* nidx */
    uint64_t nidx;
    uint32_t *fsize;   /* nf */
    uint64_t nf;
    /* glTF only (import_assimp.cpp): 2 * nv texture coordinates and
     * 4 * nv colours, NULL when the file has none; the OpenMesh readers
     * leave them NULL */
    float *uv;
    float *rgba;
} sss_om_soup;

/* Result of sss_om_read. */
typedef enum sss_om_status {
    SSS_OM_OK = 0,
    SSS_OM_READ_FAILED,    /* the reader returned false; msg says what it printed */
    SSS_OM_NO_MEMORY,      /* std::bad_alloc */
    SSS_OM_EXCEPTION       /* any other C++ exception; msg has what() */
} sss_om_status;

/* Parses data[0..len) with OpenMesh's reader for fmt through
 * OpenMesh::IO::IOManager (stream interface). omlog/omout are disabled once;
 * whatever the reader prints to omerr or std::cerr during the read is
 * captured (std::cerr is redirected meanwhile; reads are serialised by a
 * mutex). On success *out owns the soup; on failure *out is zeroed and msg
 * (msglen bytes, may be 0) holds one line, without a trailing newline. Never
 * throws. */
sss_om_status sss_om_read(const char *data, size_t len, sss_om_format fmt,
                          sss_om_soup *out, char *msg, size_t msglen);

/* Frees the arrays and zeroes the struct. NULL-safe. */
void sss_om_soup_free(sss_om_soup *s);

#ifdef __cplusplus
}
#endif
#endif
