#include "framework/model/model.hpp"

#include "framework/plugin_api/rock_material.hpp"

namespace rockdem {
Model::Model() = default;
Model::~Model() = default;
Model::Model(Model&&) noexcept = default;
Model& Model::operator=(Model&&) noexcept = default;
}  // namespace rockdem
