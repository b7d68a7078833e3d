// Variable: a tensor that remembers how it was computed, so gradients can flow back to its inputs.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/tensor/tensor.h"

namespace facetool::ag {

struct Node;

// A handle to a node of the computation graph. Variables built by core/autograd/functions.h
// record their parents and a backward function; calling backward() on a result walks the graph
// in reverse topological order. Leaves created with requires_grad=true (parameters, inputs to
// differentiate) collect their gradient in grad(); gradients accumulate across backward() calls
// until zero_grad(), as in PyTorch. The graph is freed when the last Variable referring to it
// goes away.
class Variable {
 public:
  Variable() = default;
  explicit Variable(Tensor value, bool requires_grad = false);

  bool defined() const { return node_ != nullptr; }
  const Tensor& value() const;
  const Shape& shape() const { return value().shape(); }
  Backend& backend() const { return value().backend(); }
  bool requires_grad() const;
  // The accumulated gradient (undefined until a backward pass reached this variable).
  const Tensor& grad() const;
  bool has_grad() const;
  void zero_grad();  // drops the gradient; the next backward overwrites instead of adding
  // Replaces the value (an optimiser updating a leaf in place keeps the same tensor instead).
  void set_value(Tensor value);

  // Back-propagates from this variable. A one-element result is seeded with 1; otherwise pass
  // the seed gradient (same shape as the value).
  void backward() const;
  void backward(const Tensor& seed) const;

  const std::shared_ptr<Node>& node() const { return node_; }
  explicit Variable(std::shared_ptr<Node> node) : node_(std::move(node)) {}

 private:
  std::shared_ptr<Node> node_;
};

// The same value with no history: gradients stop here (the paper's blocked visibility gradient).
Variable stop_gradient(const Variable& v);

// ---- for implementers of differentiable functions ----

// Where a backward function writes one parent's gradient: into `tensor`, overwriting it when
// `accumulate` is false (first contribution) or adding to it otherwise.
struct GradTarget {
  const Tensor* tensor = nullptr;  // nullptr: the parent needs no gradient
  bool accumulate = false;
  explicit operator bool() const { return tensor != nullptr; }
};

struct Node {
  Tensor value;
  Tensor grad;
  bool grad_written = false;  // grad holds a value (so the next contribution accumulates)
  bool requires_grad = false;
  std::string op;  // name of the function that produced it ("leaf" for leaves)
  std::vector<std::shared_ptr<Node>> parents;
  // Given this node's gradient, writes the parents' gradients through `targets` (one per
  // parent, in order).
  std::function<void(const Tensor& grad, const std::vector<GradTarget>& targets)> backward;
};

// Builds the result of a differentiable function: it requires a gradient when any parent does,
// and only then keeps the parents and the backward function.
Variable make_result(Tensor value, const char* op, std::vector<Variable> parents,
                     std::function<void(const Tensor&, const std::vector<GradTarget>&)> backward);

}  // namespace facetool::ag
