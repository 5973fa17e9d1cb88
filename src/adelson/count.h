// src/adelson/count.h — compile-time switchable operation counter (private).
#pragma once

#include "mvr/adelson/adelson.h"

namespace mvr::adelson::detail {

/// Count<true> accumulates; Count<false> compiles to nothing (the timed runs).
template <bool On>
struct Count {
    OpCounts c;
    void add(std::uint64_t n = 1) {
        if constexpr (On) c.adds += n;
    }
    void mul(std::uint64_t n = 1) {
        if constexpr (On) c.muls += n;
    }
    void cmp(std::uint64_t n = 1) {
        if constexpr (On) c.cmps += n;
    }
    void interp(std::uint64_t n = 1) {
        if constexpr (On) {
            c.interps += n;
            c.adds += n;
        }
    }
    void flush(OpCounts* out) {
        if constexpr (On) {
            if (out) *out += c;
        }
    }
};

/// Calls f.template operator()<true>() when ops is non-null, else <false>.
template <class F>
void dispatch(OpCounts* ops, F&& f) {
    if (ops)
        f.template operator()<true>();
    else
        f.template operator()<false>();
}

}  // namespace mvr::adelson::detail
