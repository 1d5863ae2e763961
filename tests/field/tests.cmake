set(RAMIFORM_field_TESTS)
