# Sourced by the consumer tests that run applications (run_install_test.sh, run_doc_projects_test.sh).
# The applications make no messenger of their own: the validation layer, enabled from the environment
# with synchronization validation, prints what it finds, and any such line fails the run. The sourcing
# script defines fail().

# Runs a command with the layer on; its output (stdout and stderr) on stdout, its failure as ours.
validated() {
  VK_INSTANCE_LAYERS=VK_LAYER_KHRONOS_validation \
    VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT "$@" 2>&1 || return 1
}

no_validation_messages() {  # <label> <output>
  if grep -qE "Validation (Error|Warning)|SYNC-HAZARD" <<<"$2"; then fail "$1: validation messages: $2"; fi
}
