// Argument checks shared by the op functions: defined, non-empty, same backend, shapes.
#pragma once

#include <initializer_list>

#include "core/tensor/tensor.h"

namespace facetool::ops::detail {

// Fails unless `t` is defined and holds at least one value.
void require_data(const char* op, const char* what, const Tensor& t);
// Fails unless `t` has rank 4.
void require_nchw(const char* op, const char* what, const Tensor& t);
// Fails unless both tensors have the same shape; the message names both shapes.
void require_same_shape(const char* op, const char* what_a, const Tensor& a, const char* what_b,
                        const Tensor& b);
// Fails unless `t` has exactly `expected` shape.
void require_shape(const char* op, const char* what, const Tensor& t, const Shape& expected);
// Fails unless every defined tensor lives on the same backend object as `first`.
void require_same_backend(const char* op, const Tensor& first,
                          std::initializer_list<const Tensor*> others);

}  // namespace facetool::ops::detail
