"""The program kinds, one package each (point, frame, pallet, conveyor, laser); codegen.protocol discovers them."""
