// Argument checks shared by the op functions. They run on every op call, so messages are only
// formatted on failure (if (!ok) fail(...), not check(ok, ...)).
#include "core/ops/checks.h"

#include "core/backend/backend.h"
#include "core/util/error.h"

namespace facetool::ops::detail {

void require_data(const char* op, const char* what, const Tensor& t) {
  check(t.defined(), op, ": ", what, " is an undefined tensor");
  if (t.numel() <= 0) fail(op, ": ", what, " is empty (shape ", t.shape().str(), ")");
}

void require_nchw(const char* op, const char* what, const Tensor& t) {
  require_data(op, what, t);
  if (t.shape().rank() != 4)
    fail(op, ": ", what, " must be NCHW (rank 4), got shape ", t.shape().str());
}

void require_same_shape(const char* op, const char* what_a, const Tensor& a, const char* what_b,
                        const Tensor& b) {
  require_data(op, what_a, a);
  require_data(op, what_b, b);
  if (a.shape() != b.shape())
    fail(op, ": shape mismatch: ", what_a, " ", a.shape().str(), " vs ", what_b, " ",
         b.shape().str());
}

void require_shape(const char* op, const char* what, const Tensor& t, const Shape& expected) {
  require_data(op, what, t);
  if (t.shape() != expected)
    fail(op, ": ", what, " has shape ", t.shape().str(), " but ", expected.str(),
         " is required");
}

void require_same_backend(const char* op, const Tensor& first,
                          std::initializer_list<const Tensor*> others) {
  for (const Tensor* t : others) {
    if (t == nullptr || !t->defined()) continue;
    if (&t->backend() != &first.backend())
      fail(op, ": tensors live on different backends ('", first.backend().name(), "' and '",
           t->backend().name(), "'); move them with Tensor::to");
  }
}

}  // namespace facetool::ops::detail
