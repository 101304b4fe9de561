"""The language server (`codegen lsp`): codegen's checker, cell schema and verify where programs are edited."""
