// The source's part of the graph contract (docs/language.md, "source"): its fixed slots and
// the fields of its graph record (a row of `sources`; its pool's DOs are built by the
// compiler, sema's make_pools). The rest of the kind is in this folder: kind.cpp (its
// descriptor row), lower.cpp (the compiler's lowering) and run.cpp (its behaviour in the
// step). An object taken out of the world goes back to its pool (engine/objects.cpp).
#pragma once

// clang-format off
#define PLANT_SLOTS_SOURCE(S) \
    S(issue, "issue", Void, In, "issue one object from the pool") \
    S(issued, "issued", Void, Out, "an object was issued") \
    S(object, "object", Ref, Out, "the object issued last; typed by `object`") \
    S(id, "id", String, Out, "the bar code of the object issued last") \
    S(issued_count, "count", Int, Out, "objects issued so far")

#define PLANT_FIELDS_SOURCE(F)                                                   \
    F(DoTypeId, do_type)                                                          \
    F(CompId, comp)                                                             \
    F(Adr<Do>, pool_adr)  /* first pooled DO id (pooled DOs are contiguous) */    \
    F(int32_t, pool_num)                                                         \
    F(double, rate)       /* issues per second, 0: only on the issue input */    \
    F(Pose, pose)         /* world pose where objects are issued */              \
    F(Adr<IdEntry>, id_adr)    /* into ids: bar codes handed out in turn */           \
    F(int32_t, id_num)
// clang-format on
