//! The STM32F407VG board: which pin and peripheral does what.
//!
//! | function          | peripheral        | pins                        | DMA            |
//! |-------------------|-------------------|-----------------------------|----------------|
//! | gyro ADC (ADS1256)| SPI1, mode 1      | PA5 SCK, PA6 MISO, PA7 MOSI, PA4 CS, PB0 DRDY (EXTI0) | DMA2 ch3 TX, ch0 RX |
//! | encoder (BiSS-C)  | SPI2, mode 2      | PB13 MA (SCK), PB14 SLO (MISO), PB15 unused MOSI | DMA1 ch4 TX, ch3 RX |
//! | inclinometer      | USART2, 115200, interrupt-buffered | PA2 TX, PA3 RX |          |
//! | host link         | USART1, 115200    | PA9 TX, PA10 RX             | DMA2 ch7 TX, ch5 RX |
//! | stepper driver    | TIM1 CH1, GPIO    | PE9 STEP (AF1), PE10 DIR    | TIM1_UP_TIM10  |
//! | gyro temperature  | ADC1 IN10         | PC0 (10 mV/C sensor)        |                |

use crate::step_timer::Tim1Steps;
use embassy_stm32::adc::{Adc, SampleTime};
use embassy_stm32::exti::{self, ExtiInput};
use embassy_stm32::flash::{self, Flash};
use embassy_stm32::gpio::{Level, Output, Pull, Speed};
use embassy_stm32::mode::Async;
use embassy_stm32::peripherals::{ADC1, PC0};
use embassy_stm32::spi::{self, Spi};
use embassy_stm32::time::Hertz;
use embassy_stm32::usart::{self, BufferedUart, Uart};
use embassy_stm32::wdg::IndependentWatchdog;
use embassy_stm32::{Config, Peri, Peripherals, bind_interrupts, dma, peripherals};
use static_cell::ConstStaticCell;

/// The independent watchdog resets the MCU when nothing has made progress for this long.
pub const WATCHDOG_US: u32 = 4_000_000;

bind_interrupts!(pub struct Irqs {
    FLASH => flash::InterruptHandler;
    EXTI0 => exti::InterruptHandler<embassy_stm32::interrupt::typelevel::EXTI0>;
    USART1 => usart::InterruptHandler<peripherals::USART1>;
    USART2 => usart::BufferedInterruptHandler<peripherals::USART2>;
    DMA1_STREAM3 => dma::InterruptHandler<peripherals::DMA1_CH3>;
    DMA1_STREAM4 => dma::InterruptHandler<peripherals::DMA1_CH4>;
    DMA2_STREAM0 => dma::InterruptHandler<peripherals::DMA2_CH0>;
    DMA2_STREAM3 => dma::InterruptHandler<peripherals::DMA2_CH3>;
    DMA2_STREAM5 => dma::InterruptHandler<peripherals::DMA2_CH5>;
    DMA2_STREAM7 => dma::InterruptHandler<peripherals::DMA2_CH7>;
});

/// 168 MHz from the 8 MHz crystal of the board.
pub fn clocks() -> Config {
    use embassy_stm32::rcc::{AHBPrescaler, APBPrescaler, Hse, HseMode, Pll, PllMul, PllPDiv, PllPreDiv, PllQDiv};
    use embassy_stm32::rcc::{PllSource, Sysclk};
    let mut c = Config::default();
    c.rcc.hse = Some(Hse {
        freq: Hertz(8_000_000),
        mode: HseMode::Oscillator,
    });
    c.rcc.pll_src = PllSource::HSE;
    c.rcc.pll = Some(Pll {
        prediv: PllPreDiv::DIV4,
        mul: PllMul::MUL168,
        divp: Some(PllPDiv::DIV2),
        divq: Some(PllQDiv::DIV7),
        divr: None,
    });
    c.rcc.ahb_pre = AHBPrescaler::DIV1;
    c.rcc.apb1_pre = APBPrescaler::DIV4;
    c.rcc.apb2_pre = APBPrescaler::DIV2;
    c.rcc.sys = Sysclk::PLL1_P;
    c
}

/// The board's devices, ready for the drivers.
pub struct Board {
    pub adc_spi: Spi<'static, Async, spi::mode::Master>,
    pub adc_cs: Output<'static>,
    pub adc_drdy: ExtiInput<'static, Async>,
    pub encoder_spi: Spi<'static, Async, spi::mode::Master>,
    pub inclinometer: BufferedUart<'static>,
    pub host: Uart<'static, Async>,
    pub step: Tim1Steps,
    pub dir: Output<'static>,
    pub thermometer: GyroThermometer,
    pub watchdog: IndependentWatchdog<'static, peripherals::IWDG>,
    pub flash: Flash<'static>,
}

/// Where the saved settings live: flash sectors 10 and 11 (offsets from the flash's start),
/// outside the program (`memory.x`).
pub const SETTINGS_FLASH: core::ops::Range<u32> = 0xC_0000..0x10_0000;

/// The gyro's temperature sensor on ADC1.
pub struct GyroThermometer {
    adc: Adc<'static, ADC1>,
    pin: Peri<'static, PC0>,
}

/// Temperatures the sensor can report; outside them it is open, shorted or not there.
const PLAUSIBLE_C: core::ops::RangeInclusive<f32> = -40.0..=125.0;

impl nf_instrument::run::Thermometer for GyroThermometer {
    fn read_c(&mut self) -> Option<f32> {
        let counts = self.adc.blocking_read(&mut self.pin, SampleTime::CYCLES480);
        // 12 bits over 3.3 V, 10 mV per degree C: a rail reading (0 or 4095) is a fault.
        let c = counts as f32 * 3300.0 / 4095.0 / 10.0;
        (counts > 0 && counts < 4095 && PLAUSIBLE_C.contains(&c)).then_some(c)
    }
}

/// Why the MCU last reset, read from RCC_CSR and cleared for the next boot.
pub fn reset_cause() -> &'static str {
    let rcc = embassy_stm32::pac::RCC;
    let csr = rcc.csr().read();
    let cause = if csr.wdgrstf() {
        "independent watchdog"
    } else if csr.wwdgrstf() {
        "window watchdog"
    } else if csr.lpwrrstf() {
        "low-power"
    } else if csr.sftrstf() {
        "software"
    } else if csr.borrstf() {
        "brown-out"
    } else if csr.porrstf() {
        "power-on"
    } else if csr.padrstf() {
        "reset pin"
    } else {
        "unknown"
    };
    rcc.csr().modify(|w| w.set_rmvf(true));
    cause
}

pub fn init(p: Peripherals) -> Board {
    let mut adc_cfg = spi::Config::default();
    adc_cfg.frequency = Hertz(1_000_000);
    adc_cfg.mode = spi::MODE_1;
    let adc_spi = Spi::new(p.SPI1, p.PA5, p.PA7, p.PA6, p.DMA2_CH3, p.DMA2_CH0, Irqs, adc_cfg);
    let mut enc_cfg = spi::Config::default();
    enc_cfg.frequency = Hertz(2_000_000);
    // BiSS-C: the clock idles high and the encoder changes its output on rising edges.
    enc_cfg.mode = spi::MODE_2;
    let encoder_spi = Spi::new(p.SPI2, p.PB13, p.PB15, p.PB14, p.DMA1_CH4, p.DMA1_CH3, Irqs, enc_cfg);
    let mut serial = usart::Config::default();
    serial.baudrate = 115_200;
    // A bad baud rate is a programming error: caught on the bench at boot, never in a run.
    // Interrupt-buffered: the line protocol is a byte stream, and no byte may be lost between reads.
    static INCL_TX: ConstStaticCell<[u8; 64]> = ConstStaticCell::new([0; 64]);
    static INCL_RX: ConstStaticCell<[u8; 256]> = ConstStaticCell::new([0; 256]);
    let inclinometer =
        BufferedUart::new(p.USART2, p.PA3, p.PA2, INCL_TX.take(), INCL_RX.take(), Irqs, serial).expect("USART2 config");
    let host = Uart::new(p.USART1, p.PA10, p.PA9, p.DMA2_CH7, p.DMA2_CH5, Irqs, serial).expect("USART1 config");
    Board {
        adc_spi,
        adc_cs: Output::new(p.PA4, Level::High, Speed::VeryHigh),
        adc_drdy: ExtiInput::new(p.PB0, p.EXTI0, Pull::Up, Irqs),
        encoder_spi,
        inclinometer,
        host,
        step: Tim1Steps::new(p.TIM1, p.PE9),
        dir: Output::new(p.PE10, Level::Low, Speed::VeryHigh),
        thermometer: GyroThermometer {
            adc: Adc::new(p.ADC1),
            pin: p.PC0,
        },
        watchdog: IndependentWatchdog::new(p.IWDG, WATCHDOG_US),
        flash: Flash::new(p.FLASH, Irqs),
    }
}
