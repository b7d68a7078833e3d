// Variable: graph nodes, the reverse-mode backward pass and stop_gradient.
#include "core/autograd/variable.h"

#include <deque>
#include <unordered_set>

#include "core/backend/backend.h"
#include "core/ops/ops.h"
#include "core/util/error.h"

namespace facetool::ag {

Variable::Variable(Tensor value, bool requires_grad) : node_(std::make_shared<Node>()) {
  check(value.defined(), "autograd: a Variable needs a defined tensor");
  node_->value = std::move(value);
  node_->requires_grad = requires_grad;
  node_->op = "leaf";
}

const Tensor& Variable::value() const {
  check(node_ != nullptr, "autograd: use of an undefined Variable");
  return node_->value;
}

bool Variable::requires_grad() const { return node_ && node_->requires_grad; }

const Tensor& Variable::grad() const {
  check(node_ != nullptr, "autograd: use of an undefined Variable");
  return node_->grad;
}

bool Variable::has_grad() const { return node_ && node_->grad_written; }

void Variable::zero_grad() {
  if (!node_) return;
  node_->grad_written = false;
}

void Variable::set_value(Tensor value) {
  check(node_ != nullptr, "autograd: use of an undefined Variable");
  check(value.shape() == node_->value.shape(), "autograd: set_value changes the shape from ",
        node_->value.shape().str(), " to ", value.shape().str());
  node_->value = std::move(value);
}

void Variable::backward() const {
  check(value().numel() == 1, "autograd: backward() without a seed needs a one-element result, ",
        "got shape ", value().shape().str(), "; pass the seed gradient");
  backward(Tensor::full(value().backend(), value().shape(), 1.0f));
}

namespace {

// Nodes reachable from `root` through nodes that require gradients, parents before children.
std::vector<Node*> topological_order(Node* root) {
  std::vector<Node*> order;
  std::unordered_set<Node*> visited;
  std::vector<std::pair<Node*, size_t>> stack{{root, 0}};
  visited.insert(root);
  while (!stack.empty()) {
    auto& [node, next] = stack.back();
    if (next < node->parents.size()) {
      Node* parent = node->parents[next++].get();
      if (parent->requires_grad && visited.insert(parent).second) stack.push_back({parent, 0});
    } else {
      order.push_back(node);
      stack.pop_back();
    }
  }
  return order;
}

void ensure_grad_storage(Node& node) {
  if (!node.grad.defined() || node.grad.shape() != node.value.shape())
    node.grad = Tensor::empty(node.value.backend(), node.value.shape());
}

}  // namespace

void Variable::backward(const Tensor& seed) const {
  check(requires_grad(), "autograd: backward() on a result that does not require a gradient ",
        "(no input was created with requires_grad=true, or a stop_gradient cut it off)");
  check(seed.shape() == value().shape(), "autograd: seed gradient ", seed.shape().str(),
        " does not match the result's shape ", value().shape().str());
  Node* root = node_.get();
  ensure_grad_storage(*root);
  if (root->grad_written)
    ops::axpy(1.0f, seed, root->grad);
  else
    ops::copy(seed, root->grad);
  root->grad_written = true;

  std::vector<Node*> order = topological_order(root);
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    Node& node = **it;
    if (!node.backward || !node.grad_written) continue;
    std::vector<GradTarget> targets(node.parents.size());
    // A parent used twice (mul(x, x)) gets a scratch gradient for its repeats, added afterwards,
    // so no backward function ever writes one tensor through two targets. std::deque keeps the
    // scratch tensors at stable addresses.
    std::deque<std::pair<Node*, Tensor>> repeats;
    std::unordered_set<Node*> seen;
    for (size_t i = 0; i < node.parents.size(); ++i) {
      Node& parent = *node.parents[i];
      if (!parent.requires_grad) continue;
      if (!seen.insert(&parent).second) {
        repeats.emplace_back(&parent, Tensor::empty(parent.value.backend(), parent.value.shape()));
        targets[i] = GradTarget{&repeats.back().second, false};
        continue;
      }
      ensure_grad_storage(parent);
      targets[i] = GradTarget{&parent.grad, parent.grad_written};
    }
    node.backward(node.grad, targets);
    for (auto& parent : node.parents)
      if (parent->requires_grad) parent->grad_written = true;
    for (auto& [parent, scratch] : repeats) ops::axpy(1.0f, scratch, parent->grad);
    // An intermediate result's gradient is no longer needed once passed on.
    if (&node != root) {
      node.grad = Tensor();
      node.grad_written = false;
    }
  }
}

Variable stop_gradient(const Variable& v) { return Variable(v.value(), false); }

Variable make_result(Tensor value, const char* op, std::vector<Variable> parents,
                     std::function<void(const Tensor&, const std::vector<GradTarget>&)> backward) {
  auto node = std::make_shared<Node>();
  node->value = std::move(value);
  node->op = op;
  for (const Variable& p : parents) {
    check(p.defined(), "autograd: ", op, " got an undefined input");
    if (p.requires_grad()) node->requires_grad = true;
  }
  if (node->requires_grad) {
    for (Variable& p : parents) node->parents.push_back(p.node());
    node->backward = std::move(backward);
  }
  return Variable(node);
}

}  // namespace facetool::ag
