//! `motionhdl.svd`: the register map as a CMSIS-SVD 1.3 device description,
//! for debuggers (register views) and code generators such as svd2rust.
//!
//! The map becomes an `svd_rs::Device` and `svd_encoder` writes the XML, so
//! the file is valid by the same library that svd2rust reads it with.

use super::{
    block_byte_offset, block_span_bytes, layout, memory_bytes, register_doc, stride_bytes, Member,
    FSMC_NE1_BASE, REGISTER_BYTES,
};
use motionhdl_hdl::{banner, VERSION};
use motionhdl_model::regmap::{Access, Block, BusMap, Field, Memory, Register, RegisterArray};
use svd_encoder::{Config, NumberFormat};
use svd_rs::{
    AddressBlock, AddressBlockUsage, BitRange, ClusterInfo, Device, DimElement, EnumeratedValue,
    EnumeratedValues, FieldInfo, ModifiedWriteValues, Peripheral, PeripheralInfo, RegisterCluster,
    RegisterInfo, RegisterProperties, SvdError, ValidateLevel, WriteConstraint,
    WriteConstraintRange,
};

/// The file name (at the top of the generated tree).
pub const FILE_NAME: &str = "motionhdl.svd";

/// SVD's access type; write-one-to-clear is read-write plus
/// `modifiedWriteValues`.
fn access(a: Access) -> svd_rs::Access {
    match a {
        Access::ReadOnly => svd_rs::Access::ReadOnly,
        Access::WriteOnly => svd_rs::Access::WriteOnly,
        Access::ReadWrite | Access::WriteOneToClear => svd_rs::Access::ReadWrite,
    }
}

fn modified_write_values(a: Access) -> Option<ModifiedWriteValues> {
    (a == Access::WriteOneToClear).then_some(ModifiedWriteValues::OneToClear)
}

/// Every builder validates strictly, so a map that svd-parser would reject
/// fails `generate` before a byte is written rather than in a debugger.
const LEVEL: ValidateLevel = ValidateLevel::Strict;

fn properties(size: u32, reset: u32, mask: u32) -> Result<RegisterProperties, SvdError> {
    RegisterProperties::new()
        .size(Some(size))
        .access(Some(svd_rs::Access::ReadWrite))
        .reset_value(Some(reset.into()))
        .reset_mask(Some(mask.into()))
        .build(LEVEL)
}

/// An array of `count` elements `increment` bytes apart. No dimIndex: the
/// names are `NAME[%s]`, which CMSIS-SVD indexes 0..count-1 itself (a
/// dimIndex belongs to `%s` lists).
fn dim(count: u32, increment: u32) -> Result<DimElement, SvdError> {
    DimElement::builder()
        .dim(count)
        .dim_increment(increment)
        .build(LEVEL)
}

/// What firmware may write to a writable field: one of its enumerated
/// values, or any value of its width. Declared so that svd2rust gives a
/// safe writer instead of `unsafe { bits() }`.
fn write_constraint(f: &Field) -> Option<WriteConstraint> {
    if f.access == Access::ReadOnly {
        return None;
    }
    Some(if f.values.is_empty() {
        WriteConstraint::Range(WriteConstraintRange {
            min: 0,
            max: (1u64 << f.width) - 1,
        })
    } else {
        WriteConstraint::UseEnumeratedValues(true)
    })
}

fn field(f: &Field) -> Result<svd_rs::Field, SvdError> {
    let mut values = Vec::new();
    if !f.values.is_empty() {
        let list = f
            .values
            .iter()
            .map(|v| {
                EnumeratedValue::builder()
                    .name(v.name.into())
                    .description(Some(v.description.into()))
                    .value(Some(v.value.into()))
                    .build(LEVEL)
            })
            .collect::<Result<_, _>>()?;
        values.push(EnumeratedValues::builder().values(list).build(LEVEL)?);
    }
    Ok(FieldInfo::builder()
        .name(f.name.into())
        .description(Some(f.description.into()))
        .bit_range(BitRange::from_offset_width(f.lsb, f.width))
        .access(Some(access(f.access)))
        .modified_write_values(modified_write_values(f.access))
        .write_constraint(write_constraint(f))
        .enumerated_values(values)
        .build(LEVEL)?
        .single())
}

fn register(r: &Register) -> Result<RegisterCluster, SvdError> {
    let fields = r.fields.iter().map(field).collect::<Result<Vec<_>, _>>()?;
    let info = RegisterInfo::builder()
        .name(r.name.into())
        .description(Some(register_doc(r)))
        .address_offset(r.offset * REGISTER_BYTES)
        .properties(properties(32, r.reset, u32::MAX)?.access(Some(access(r.access))))
        .modified_write_values(modified_write_values(r.access))
        .fields((!fields.is_empty()).then_some(fields))
        .build(LEVEL)?;
    Ok(info.single().into())
}

fn cluster(b: &Block, a: &RegisterArray) -> Result<RegisterCluster, SvdError> {
    let children = a.registers.iter().map(register).collect::<Result<_, _>>()?;
    let info = ClusterInfo::builder()
        .name(format!("{}[%s]", a.name))
        .description(Some(format!("{} {}: {} elements", b.name, a.name, a.count)))
        .address_offset(a.offset * REGISTER_BYTES)
        .children(children)
        .build(LEVEL)?;
    Ok(info.array(dim(a.count, stride_bytes(a))?).into())
}

fn peripheral(
    map: &BusMap,
    name: &str,
    description: &str,
    byte_offset: u32,
    block: AddressBlock,
    registers: Vec<RegisterCluster>,
) -> Result<Peripheral, SvdError> {
    Ok(PeripheralInfo::builder()
        .name(name.into())
        .description(Some(description.into()))
        .group_name(Some(map.name.into()))
        .base_address((FSMC_NE1_BASE + byte_offset).into())
        .address_block(Some(vec![block]))
        .registers(Some(registers))
        .build(LEVEL)?
        .single())
}

fn block_peripheral(map: &BusMap, b: &Block) -> Result<Peripheral, SvdError> {
    let registers = layout(&b.registers, &b.arrays, None)
        .0
        .into_iter()
        .filter_map(|(_, m)| match m {
            Member::Register(r) => Some(register(r)),
            Member::Array(a) => Some(cluster(b, a)),
            Member::Reserved { .. } => None,
        })
        .collect::<Result<_, _>>()?;
    let block = AddressBlock::builder()
        .offset(0)
        .size(block_span_bytes(b))
        .usage(AddressBlockUsage::Registers)
        .build(LEVEL)?;
    peripheral(
        map,
        b.name,
        b.description,
        block_byte_offset(b),
        block,
        registers,
    )
}

fn memory_peripheral(map: &BusMap, m: &Memory) -> Result<Peripheral, SvdError> {
    let words = RegisterInfo::builder()
        .name("WORD[%s]".into())
        .description(Some(format!(
            "One {}-bit word; access it as a {}-bit halfword.",
            m.word_bits, m.word_bits
        )))
        .address_offset(0)
        // The RAM's contents after reset are not defined: mask 0.
        .properties(properties(m.word_bits, 0, 0)?)
        .build(LEVEL)?
        .array(dim(m.words, m.word_bits / 8)?);
    let block = AddressBlock::builder()
        .offset(0)
        .size(memory_bytes(m))
        .usage(AddressBlockUsage::Buffer)
        .build(LEVEL)?;
    peripheral(
        map,
        m.name,
        m.description,
        m.byte_offset,
        block,
        vec![words.into()],
    )
}

/// The register map as an SVD device, its peripherals at `FSMC_NE1_BASE`
/// plus their byte offsets.
pub fn device(map: &BusMap) -> Result<Device, SvdError> {
    let mut peripherals = Vec::new();
    for b in &map.blocks {
        peripherals.push(block_peripheral(map, b)?);
    }
    for m in &map.memories {
        peripherals.push(memory_peripheral(map, m)?);
    }
    Device::builder()
        .vendor(Some("motionhdl".into()))
        .name(map.name.into())
        .version(VERSION.into())
        .description(format!(
            "{}. Base address: STM32F4 FSMC bank 1 region 1 (NE1); move every peripheral \
             for another chip select. {}",
            map.description,
            super::access_rule()
        ))
        .address_unit_bits(8)
        .width(32)
        .default_register_properties(properties(32, 0, u32::MAX)?)
        .peripherals(peripherals)
        .schema_version("1.3".into())
        .xmlns_xs("http://www.w3.org/2001/XMLSchema-instance".into())
        .no_namespace_schema_location("CMSIS-SVD.xsd".into())
        .build(LEVEL)
}

/// The CMSIS-SVD 1.3 file of `map`: the banner comment, then the device.
///
/// Panics if the map is not a valid SVD device (a broken table, caught by
/// the tests for every configuration they build).
pub fn svd(map: &BusMap) -> String {
    let dev = device(map).unwrap_or_else(|e| panic!("{} is not a valid SVD device: {e}", map.name));
    // Register sizes in decimal (`<size>32</size>`), as SVD files usually
    // spell them; the encoder's other defaults already match.
    let config = Config::default().register_size(NumberFormat::Dec);
    let xml = svd_encoder::encode_with_config(&dev, &config).expect("svd-encoder never fails");
    // Every generated file starts with the banner, so the optional XML
    // declaration goes (the encoding is UTF-8, XML's default).
    let body = match xml.strip_prefix("<?xml") {
        Some(rest) => rest.split_once("?>").expect("closed declaration").1,
        None => &xml,
    };
    format!("<!-- {} -->\n{}\n", banner(), body.trim())
}
