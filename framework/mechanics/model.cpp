#include "framework/mechanics/model.hpp"

#include "models/rock/rock_material.hpp"

namespace rockdem {
Model::Model() = default;
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
}  // namespace rockdem
